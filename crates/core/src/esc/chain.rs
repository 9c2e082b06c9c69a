//! The extended simplicial chain of a closed PN surface (the paper's §4) and its associated
//! function: point-in-solid.
//!
//! For a closed, consistently oriented triangle mesh with vertex normals (each shell turned to face
//! the way its nesting says first, [`crate::mesh::orient_shells`]; the PN surface keeps the mesh's
//! creases, [`super::pn`]), the chain is
//! `δ = Σᵢ sᵢ·Sᵢ + Σᵢ aᵢ·ffcᵢ`, one term of each kind per triangle `tᵢ`:
//!
//! - the *original simplex* `Sᵢ`, the tetrahedron of `tᵢ` and an apex `A`, with `sᵢ` the sign of its
//!   signed volume. Containment is decided by exact orientation predicates with one symbolic
//!   perturbation of the query point ([`super::predicates`]), so `Σ sᵢ·[Q ∈ Sᵢ]` is the flat
//!   mesh's winding number at `Q`, exactly, even for points on a shared face or on the mesh.
//! - the *free-form cell* `ffcᵢ` between `tᵢ` and its PN patch `bᵢ`. Its lateral walls are where
//!   this implementation departs from the paper's Definition 8, which bounds the cell by the plane
//!   through each edge parallel to the mean of the two triangle normals. A PN edge is a space curve
//!   that leaves that plane (the paper's own Fig. 7), so planar walls leave slivers between the patch
//!   and a plane that belong to neither or both neighbouring cells. Here the wall of an edge is the
//!   ruled strip from the straight edge to the curved one ([`Wall`]); it contains the plane's part
//!   where the curved edge lies in it, and it is one surface shared by the two neighbouring cells
//!   with opposite orientations, so the cells tile the shell between the mesh and the PN surface
//!   exactly. The cell's coefficient at `Q` is the winding number of its boundary (patch, reversed
//!   base triangle, three walls) around `Q`: `+1` on the side of the base triangle its normal points
//!   to, `−1` on the other, one value per connected part, as the paper's sign rule gives.
//!
//! `f(Q) = Σ sᵢ·[Q ∈ Sᵢ] + Σ (winding of ffcᵢ at Q)` is 1 inside the solid bounded by the PN
//! surface and 0 outside.
//!
//! **Why this apex.** The paper takes the origin, to make coefficients cheap. Any point gives a
//! normal chain, but the work of a query is the number of tetrahedra whose cone from the apex holds
//! it. From the origin, a mesh far away is seen in a narrow cone, and every query there is in the
//! cones of many triangles; from a point inside a star-shaped solid, each direction meets the
//! surface once and most queries are in one cone. So [`EscSolid`] tries the volume centroid, the
//! vertex mean and the box centre, and keeps the one with the fewest tetrahedra of negative sign
//! (triangles seen from behind, which double the cones over them).
//!
//! **Speed.** The tetrahedra all share the apex, so they are indexed by direction: a cube map around
//! the apex lists, per cell, the triangles whose cone meets it. A free-form cell lies in the convex
//! hull of its patch's ten control points, and for a fine mesh it is thin, so a uniform grid over
//! their bounding boxes plus a bounding polytope per cell (its frame's box cut by six slabs) rejects
//! almost every query without touching a patch: most queries compute no ray–patch intersection at
//! all. A coarse mesh with rounded edges (a cube with a crease angle of 180°) has thick cells, and a
//! query in the shell between the mesh and its PN surface computes one; a Boolean's surface
//! ([`super::draw::Boolean::surface`]) asks the solids only near their surfaces. Ray parity
//! ([`EscSolid::parity_value`]), the classic test, walks a ray through the same grid and intersects
//! every patch whose box it meets.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;

use super::pn::{DEFAULT_CREASE_ANGLE, PnSurface, creases, cubic_index, valid_crease_angle};
use super::predicates::{orient_sign, side};
use super::ray::{Crossings, Ray, Unsure, Wall, patch_crossings, patch_hits};
use crate::mesh::Mesh;
use crate::mesh::{MeshDefects, ShellError, orient_shells, validate};

/// Why a mesh cannot make an [`EscSolid`].
#[derive(Clone, Debug, PartialEq)]
pub enum EscError {
    /// The mesh is not a closed, consistently oriented 2-manifold.
    Defects(MeshDefects),
    /// The mesh has no triangles.
    Empty,
    /// `normals` is not one finite unit vector per vertex.
    Normals,
    /// A coordinate is not finite.
    NotFinite,
    /// The crease angle is not a finite number of degrees from 0 to 180.
    CreaseAngle {
        /// The angle given.
        degrees: f64,
    },
    /// The shells (connected pieces) of the mesh cannot be oriented: two cross each other (see
    /// [`ShellError::Intersect`] for what is detected), or too many overlap.
    Shells(ShellError),
}

impl fmt::Display for EscError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Defects(d) => write!(f, "{d}"),
            Self::Empty => f.write_str("the mesh has no triangles"),
            Self::Normals => f.write_str("the mesh needs one unit normal per vertex"),
            Self::NotFinite => f.write_str("a vertex coordinate is not a finite number"),
            Self::CreaseAngle { degrees } => write!(
                f,
                "the crease angle must be a number of degrees from 0 to 180, not {degrees}"
            ),
            Self::Shells(e) => write!(f, "{e}"),
        }
    }
}

impl core::error::Error for EscError {}

/// Work counters of queries, for benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Queries answered.
    pub queries: u64,
    /// Tetrahedra tested with orientation predicates.
    pub tetrahedra: u64,
    /// Ray–patch intersection computations (free-form cells for ESC, patches for ray parity).
    pub patch_intersections: u64,
    /// Rays cast again because a crossing sat on a seam or grazed.
    pub retries: u64,
    /// Queries where every ray was unsure (answered with the last guess).
    pub unsure: u64,
}

/// A free-form cell's bounding polytope and walls.
///
/// The cell lies in the convex hull of its patch's ten control points (its patch does, its base
/// triangle's corners are control points, and each wall's rulings join a point of the base edge to
/// a point of the curved edge), so the hull's extents along a few directions bound it: the frame's
/// box, and six slabs that cut the box's corners. The box alone is a loose bound for a large cell:
/// a right triangle's box is the square over it, and a patch that bulges far from its base (a
/// coarse mesh with rounded edges, such as a cube with a crease angle of 180°, whose corner normals
/// are far from its face normals) fills the box's top only near its middle. The slabs are the base
/// triangle's three in-plane edge normals (the box becomes a prism over the triangle) and its three
/// corner normals (each corner's tangent plane, which its edge control points lie in unless the
/// edge is a crease, caps the box's top corner there).
#[derive(Clone, Copy, Debug)]
struct Cell {
    /// Frame axes: edge direction, in-plane perpendicular, and the base triangle's unit normal
    /// (counter-clockwise).
    axes: [DVec3; 3],
    /// The box in the frame: `lo ≤ (p·axes) ≤ hi`.
    lo: DVec3,
    hi: DVec3,
    /// More directions, with the hull's extent along each: `slab_lo ≤ p·slabs ≤ slab_hi`.
    slabs: [DVec3; 6],
    slab_lo: [f64; 6],
    slab_hi: [f64; 6],
    /// The walls of edges 0→1, 1→2, 2→0 and whether the triangle runs them as stored (`1`) or
    /// reversed (`−1`).
    walls: [(u32, i8); 3],
}

impl Cell {
    /// The bounding polytope of the cell `net` over the triangle `corners` with unit vertex
    /// normals `normals`, padded by a hair for rounding.
    fn new(
        corners: [DVec3; 3],
        normals: [DVec3; 3],
        net: &super::pn::CubicNet,
        walls: [(u32, i8); 3],
    ) -> Self {
        let [a, b, c] = corners;
        let normal = (b - a).cross(c - a).normalize_or_zero();
        let x = (b - a).normalize_or_zero();
        let y = normal.cross(x);
        let axes = [x, y, normal];
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        for p in net {
            let l = DVec3::new(p.dot(x), p.dot(y), p.dot(normal));
            lo = lo.min(l);
            hi = hi.max(l);
        }
        let size = (hi - lo).max_element().max(1e-300);
        let pad = 1e-9 * size + 1e-12 * lo.abs().max(hi.abs()).max_element();
        let mut slabs = [DVec3::ZERO; 6];
        for (k, slab) in slabs[..3].iter_mut().enumerate() {
            // Outward in the triangle's plane across the edge from corner k to corner k + 1.
            let edge = corners[(k + 1) % 3] - corners[k];
            *slab = edge.cross(normal).normalize_or_zero();
        }
        slabs[3..].copy_from_slice(&normals);
        let mut slab_lo = [f64::INFINITY; 6];
        let mut slab_hi = [f64::NEG_INFINITY; 6];
        for (k, d) in slabs.iter().enumerate() {
            for p in net {
                slab_lo[k] = slab_lo[k].min(p.dot(*d));
                slab_hi[k] = slab_hi[k].max(p.dot(*d));
            }
            let pad = 1e-9 * size + 1e-12 * slab_lo[k].abs().max(slab_hi[k].abs());
            slab_lo[k] -= pad;
            slab_hi[k] += pad;
        }
        Self {
            axes,
            lo: lo - pad,
            hi: hi + pad,
            slabs,
            slab_lo,
            slab_hi,
            walls,
        }
    }

    /// Whether the segment `origin + λ·dir`, `0 ≤ λ ≤ max`, meets the bounding polytope (which
    /// holds the patch too): the segment clipped by each slab in turn.
    fn meets(&self, origin: DVec3, dir: DVec3, max: f64) -> bool {
        let (mut near, mut far) = (0.0_f64, max);
        let slabs = self
            .axes
            .iter()
            .zip(self.lo.to_array().into_iter().zip(self.hi.to_array()));
        for (d, (lo, hi)) in slabs.chain(
            self.slabs.iter().zip(
                self.slab_lo
                    .iter()
                    .copied()
                    .zip(self.slab_hi.iter().copied()),
            ),
        ) {
            let (o, v) = (origin.dot(*d), dir.dot(*d));
            if v == 0.0 {
                if o < lo || o > hi {
                    return false;
                }
                continue;
            }
            let (t0, t1) = ((lo - o) / v, (hi - o) / v);
            near = near.max(t0.min(t1));
            far = far.min(t0.max(t1));
            if near > far {
                return false;
            }
        }
        true
    }

    /// Whether `q` is in the bounding polytope (every point of the cell is).
    fn holds(&self, q: DVec3) -> bool {
        let p = DVec3::new(
            q.dot(self.axes[0]),
            q.dot(self.axes[1]),
            q.dot(self.axes[2]),
        );
        p.cmpge(self.lo).all()
            && p.cmple(self.hi).all()
            && self
                .slabs
                .iter()
                .zip(self.slab_lo.iter().zip(&self.slab_hi))
                .all(|(d, (&lo, &hi))| (lo..=hi).contains(&q.dot(*d)))
    }
}

/// How to make an [`EscSolid`]: [`EscSolid::with_options`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EscOptions {
    /// The crease angle in degrees, from 0 to 180: an edge whose two triangles' normals differ by
    /// more is kept sharp (see [`super::pn`]); 180 rounds every edge. [`DEFAULT_CREASE_ANGLE`] by
    /// default.
    pub crease_angle: f64,
    /// The apex of the original simplices; `None` (the default) chooses one as the module says.
    pub apex: Option<DVec3>,
}

impl Default for EscOptions {
    fn default() -> Self {
        Self {
            crease_angle: DEFAULT_CREASE_ANGLE,
            apex: None,
        }
    }
}

/// A solid bounded by the PN surface of a closed triangle mesh, as an extended simplicial chain
/// (see the module documentation).
#[derive(Clone, Debug)]
pub struct EscSolid {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    pn: PnSurface,
    apex: DVec3,
    crease_angle: f64,
    crease_edges: usize,
    shells: usize,
    shells_turned_over: usize,
    /// The sign of each original simplex (0 for a flat one).
    coefficients: Vec<i8>,
    cube: CubeMap,
    cells: Vec<Cell>,
    walls: Vec<Wall>,
    grid: Grid,
}

/// Directions tried in turn for a cell's ray, as tilts from its base normal.
const TILTS: [(f64, f64); 6] = [
    (0.0, 0.0),
    (0.31, 0.17),
    (-0.23, 0.29),
    (0.13, -0.37),
    (-0.41, -0.11),
    (0.07, 0.43),
];

/// Directions tried in turn by ray parity.
const PARITY_DIRECTIONS: [[f64; 3]; 4] = [
    [0.539_3, 0.807_1, 0.241_2],
    [-0.613_7, 0.283_1, 0.737_3],
    [0.171_9, -0.521_3, 0.835_9],
    [-0.334_1, -0.774_5, -0.537_2],
];

impl EscSolid {
    /// The chain of `mesh`, a closed, consistently oriented triangle mesh with one unit normal per
    /// vertex, with the apex chosen as the module says and the edges sharper than
    /// [`DEFAULT_CREASE_ANGLE`] kept sharp.
    ///
    /// Each shell (connected piece) of the mesh is turned over first if it faces the wrong way for
    /// its nesting: outward at the outside, inward around a cavity ([`orient_shells`];
    /// [`EscSolid::shells_turned_over`] counts them).
    ///
    /// # Errors
    ///
    /// [`EscError`] when the mesh is empty, not closed and consistently oriented, has a coordinate
    /// that is not finite, lacks unit normals, or has shells that visibly cross.
    pub fn new(mesh: &Mesh) -> Result<Self, EscError> {
        Self::with_options(mesh, EscOptions::default())
    }

    /// The chain of `mesh` with the apex `apex` (the paper uses the origin).
    ///
    /// # Errors
    ///
    /// As [`EscSolid::new`], and [`EscError::NotFinite`] for an apex that is not finite.
    pub fn with_apex(mesh: &Mesh, apex: DVec3) -> Result<Self, EscError> {
        Self::with_options(
            mesh,
            EscOptions {
                apex: Some(apex),
                ..EscOptions::default()
            },
        )
    }

    /// The chain of `mesh` with the crease angle `degrees` (0 to 180; 180 rounds every edge): an
    /// edge whose two triangles' normals differ by more is kept sharp.
    ///
    /// # Errors
    ///
    /// As [`EscSolid::new`], and [`EscError::CreaseAngle`] for an angle that is not a finite number
    /// from 0 to 180.
    pub fn with_crease_angle(mesh: &Mesh, degrees: f64) -> Result<Self, EscError> {
        Self::with_options(
            mesh,
            EscOptions {
                crease_angle: degrees,
                ..EscOptions::default()
            },
        )
    }

    /// The chain of `mesh` made as `options` say.
    ///
    /// # Errors
    ///
    /// As [`EscSolid::new`], [`EscError::CreaseAngle`] for a crease angle that is not a finite
    /// number from 0 to 180, and [`EscError::NotFinite`] for an apex that is not finite.
    pub fn with_options(mesh: &Mesh, options: EscOptions) -> Result<Self, EscError> {
        if !valid_crease_angle(options.crease_angle) {
            return Err(EscError::CreaseAngle {
                degrees: options.crease_angle,
            });
        }
        check(mesh)?;
        if options.apex.is_some_and(|a| !a.is_finite()) {
            return Err(EscError::NotFinite);
        }
        let mut mesh = mesh.clone();
        let shells = orient_shells(&mut mesh).map_err(EscError::Shells)?;
        let apex = options
            .apex
            .unwrap_or_else(|| choose_apex(&mesh.positions, &mesh.triangles));
        let mut solid = Self::build(mesh, apex, options.crease_angle);
        solid.shells = shells.shells;
        solid.shells_turned_over = shells.turned_over;
        Ok(solid)
    }

    fn build(mesh: Mesh, apex: DVec3, crease_angle: f64) -> Self {
        let creases = creases(&mesh, crease_angle);
        let pn = PnSurface::creased(&mesh, &creases);
        let Mesh {
            positions,
            triangles,
            ..
        } = mesh;
        let coefficients: Vec<i8> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                orient_sign(a, b, c, apex)
            })
            .collect();
        let cube = CubeMap::new(apex, &positions, &triangles, &coefficients);
        // Walls: one per undirected edge, stored from the lower vertex index to the higher.
        let mut edges: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(triangles.len() * 3);
        for (t, tri) in triangles.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                edges.push((a.min(b), a.max(b), t as u32, e as u8));
            }
        }
        edges.sort_unstable();
        let mut walls = Vec::with_capacity(edges.len() / 2);
        let mut cell_walls = vec![[(0u32, 0i8); 3]; triangles.len()];
        for group in edges.chunk_by(|x, y| x.0 == y.0 && x.1 == y.1) {
            let (lo, hi, t, e) = group[0];
            let tri = triangles[t as usize];
            let net = &pn.patches[t as usize];
            // The curved edge e of patch t runs from corner e to corner e + 1; its inner points.
            let [c1, c2] = edge_inner(net, e as usize);
            let a = tri[e as usize];
            let wall = if a == lo {
                Wall::new(positions[lo as usize], positions[hi as usize], c1, c2)
            } else {
                Wall::new(positions[lo as usize], positions[hi as usize], c2, c1)
            };
            let index = walls.len() as u32;
            walls.push(wall);
            for &(_, _, t, e) in group {
                let tri = triangles[t as usize];
                let forward = tri[e as usize] == lo;
                cell_walls[t as usize][e as usize] = (index, if forward { 1 } else { -1 });
            }
        }
        let cells: Vec<Cell> = triangles
            .iter()
            .zip(&pn.patches)
            .zip(&cell_walls)
            .enumerate()
            .map(|(t, ((tri, net), &walls))| {
                let corners = tri.map(|i| positions[i as usize]);
                Cell::new(corners, pn.corner_normals(t), net, walls)
            })
            .collect();
        let boxes: Vec<(DVec3, DVec3)> = pn
            .patches
            .iter()
            .map(|net| {
                let (lo, hi) = net
                    .iter()
                    .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
                        (lo.min(p), hi.max(p))
                    });
                let pad = 1e-9 * (hi - lo).max_element().max(1e-300);
                (lo - pad, hi + pad)
            })
            .collect();
        let grid = Grid::new(&boxes);
        Self {
            positions,
            triangles,
            pn,
            apex,
            crease_angle,
            crease_edges: creases.edges,
            shells: 1,
            shells_turned_over: 0,
            coefficients,
            cube,
            cells,
            walls,
            grid,
        }
    }

    /// The apex of the original simplices.
    #[must_use]
    pub fn apex(&self) -> DVec3 {
        self.apex
    }

    /// The PN surface.
    #[must_use]
    pub fn surface(&self) -> &PnSurface {
        &self.pn
    }

    /// The crease angle the solid was made with, in degrees.
    #[must_use]
    pub fn crease_angle(&self) -> f64 {
        self.crease_angle
    }

    /// The number of the mesh's edges kept sharp (creases).
    #[must_use]
    pub fn crease_edges(&self) -> usize {
        self.crease_edges
    }

    /// The number of shells (connected pieces) of the mesh's surface.
    #[must_use]
    pub fn shells(&self) -> usize {
        self.shells
    }

    /// The number of shells that faced the wrong way for their nesting and were turned over
    /// (outward at even depth, inward around a cavity): 0 for a well-oriented mesh.
    #[must_use]
    pub fn shells_turned_over(&self) -> usize {
        self.shells_turned_over
    }

    /// The mesh's vertices.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The mesh's triangles, with every shell facing the way its nesting says (see
    /// [`EscSolid::new`]).
    #[must_use]
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The coefficients `sᵢ` of the original simplices (`±1`, or 0 for a triangle whose plane holds
    /// the apex).
    #[must_use]
    pub fn coefficients(&self) -> &[i8] {
        &self.coefficients
    }

    /// The axis-aligned box of the PN surface's control points (it holds the solid).
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (self.grid.lo, self.grid.hi)
    }

    /// Whether `q` is in the solid: `f(q) = 1`.
    #[must_use]
    pub fn contains(&self, q: DVec3) -> bool {
        self.value(q, &mut Stats::default()) == 1
    }

    /// The chain's associated function `f(q)`: 1 in the solid, 0 outside.
    #[must_use]
    pub fn value(&self, q: DVec3, stats: &mut Stats) -> i32 {
        stats.queries += 1;
        if let Some(cells) = self.cells_at(q, stats) {
            return self.flat_value(q, stats) + cells;
        }
        // `q` is on a cell's boundary (a wall between two cells, or a patch), where no ray tells
        // which side it is on: the whole chain is evaluated at one point moved off it by a hair
        // in a fixed direction, the tetrahedra too, so that both parts describe the same point.
        let (lo, hi) = self.bounds();
        let moved = q + DVec3::new(0.539_3, 0.807_1, 0.241_2) * (1e-9 * (hi - lo).max_element());
        match self.cells_at(moved, stats) {
            Some(cells) => self.flat_value(moved, stats) + cells,
            None => {
                stats.unsure += 1;
                self.flat_value(q, stats)
            }
        }
    }

    /// `Σ sᵢ·[q ∈ Sᵢ]`: the winding number of the flat mesh at `q` (the chain without its
    /// free-form cells), exact.
    #[must_use]
    pub fn flat_value(&self, q: DVec3, stats: &mut Stats) -> i32 {
        let a = self.apex;
        let mut sum = 0;
        for &t in self.cube.cell(q - a) {
            let s = self.coefficients[t as usize];
            let [p0, p1, p2] = self.triangles[t as usize].map(|i| self.positions[i as usize]);
            stats.tetrahedra += 1;
            // q and the apex on the same side of the triangle, and q inside the cone: the three
            // faces through the apex have q on the side of the opposite vertex (sign −s, see
            // the derivation in the tests).
            if side(p0, p1, p2, q) == s
                && side(a, p1, p2, q) == -s
                && side(p0, a, p2, q) == -s
                && side(p0, p1, a, q) == -s
            {
                sum += i32::from(s);
            }
        }
        sum
    }

    /// `Σ (winding of ffcᵢ at q)`: the free-form cells' part of `f(q)`; `None` where `q` is on a
    /// cell's boundary.
    #[must_use]
    pub fn cells_at(&self, q: DVec3, stats: &mut Stats) -> Option<i32> {
        let mut sum = 0;
        for &t in self.grid.cell(q) {
            if self.cells[t as usize].holds(q) {
                sum += self.cell_winding(t as usize, q, stats)?;
            }
        }
        Some(sum)
    }

    /// The winding number of the boundary of free-form cell `t` around `q`; `None` when no ray
    /// tells (`q` on the cell's boundary: its patch or a wall).
    fn cell_winding(&self, t: usize, q: DVec3, stats: &mut Stats) -> Option<i32> {
        let cell = &self.cells[t];
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize]);
        // Cast away from the base triangle's plane, so the ray never meets the base triangle.
        let up = match side(a, b, c, q) {
            0 => return Some(0),
            s if s < 0 => cell.axes[2],
            _ => -cell.axes[2],
        };
        for (k, &(x, y)) in TILTS.iter().enumerate() {
            if k > 0 {
                stats.retries += 1;
            }
            let dir = up + cell.axes[0] * x + cell.axes[1] * y;
            let ray = Ray::new(q, dir, f64::INFINITY);
            stats.patch_intersections += 1;
            let mut count = patch_crossings(&self.pn.patches[t], &ray);
            for &(w, orientation) in &cell.walls {
                count = count.plus(match self.walls[w as usize].crossings(&ray) {
                    Crossings::Count(n) => Crossings::Count(n * i32::from(orientation)),
                    Crossings::Unsure => Crossings::Unsure,
                });
            }
            if let Crossings::Count(n) = count {
                return Some(n);
            }
        }
        None
    }

    /// Jordan ray parity against the PN surface, with the same grid: a ray from `q` walks the grid
    /// and every patch whose box it meets is intersected; `q` is inside when the crossings are odd.
    /// Returns 1 inside, 0 outside. The reference ESC is compared with, and its peer in benchmarks.
    #[must_use]
    pub fn parity_value(&self, q: DVec3, stats: &mut Stats, seen: &mut Vec<u32>) -> i32 {
        stats.queries += 1;
        for (k, d) in PARITY_DIRECTIONS.iter().enumerate() {
            if k > 0 {
                stats.retries += 1;
            }
            let ray = Ray::new(q, DVec3::from_array(*d), f64::INFINITY);
            seen.clear();
            self.grid.walk(&ray, |items| seen.extend_from_slice(items));
            seen.sort_unstable();
            seen.dedup();
            let mut count = Crossings::Count(0);
            for &t in seen.iter() {
                let (lo, hi) = self.grid.boxes[t as usize];
                if !ray_hits_box(&ray, lo, hi) {
                    continue;
                }
                stats.patch_intersections += 1;
                count = count.plus(patch_crossings(&self.pn.patches[t as usize], &ray));
                if count == Crossings::Unsure {
                    break;
                }
            }
            if let Crossings::Count(n) = count {
                return n.rem_euclid(2);
            }
        }
        stats.unsure += 1;
        0
    }

    /// Every crossing of the segment from `p0` to `p1` with the PN surface, as `(distance from p0,
    /// triangle, barycentric coordinates, sign)` in no particular order.
    ///
    /// # Errors
    ///
    /// [`Unsure`] where a crossing sits on a seam between patches or the segment grazes one.
    pub fn segment_hits(
        &self,
        p0: DVec3,
        p1: DVec3,
        out: &mut Vec<(f64, u32, DVec3, i8)>,
    ) -> Result<(), Unsure> {
        let len = (p1 - p0).length();
        if len == 0.0 {
            return Ok(());
        }
        let ray = Ray::new(p0, p1 - p0, len);
        let mut seen: Vec<u32> = Vec::new();
        self.grid.walk(&ray, |items| seen.extend_from_slice(items));
        seen.sort_unstable();
        seen.dedup();
        for &t in &seen {
            let (lo, hi) = self.grid.boxes[t as usize];
            if !ray_hits_box(&ray, lo, hi)
                || !self.cells[t as usize].meets(ray.origin, ray.dir, len)
            {
                continue;
            }
            patch_hits(&self.pn.patches[t as usize], &ray, &mut |h| {
                out.push((h.lambda, t, h.bary, h.sign));
            })?;
        }
        Ok(())
    }
}

fn check(mesh: &Mesh) -> Result<(), EscError> {
    if mesh.triangles.is_empty() {
        return Err(EscError::Empty);
    }
    if mesh.positions.iter().any(|p| !p.is_finite()) {
        return Err(EscError::NotFinite);
    }
    if mesh.normals.len() != mesh.positions.len()
        || mesh
            .normals
            .iter()
            .any(|n| !n.is_finite() || (n.length() - 1.0).abs() > 1e-6)
    {
        return Err(EscError::Normals);
    }
    validate(&mesh.positions, &mesh.triangles).map_err(EscError::Defects)
}

/// The inner control points of curved edge `e` of a cubic net, from corner `e` to corner `e + 1`
/// (corners `P300`, `P030`, `P003`).
fn edge_inner(net: &super::pn::CubicNet, e: usize) -> [DVec3; 2] {
    match e {
        0 => [net[cubic_index(2, 1)], net[cubic_index(1, 2)]],
        1 => [net[cubic_index(0, 2)], net[cubic_index(0, 1)]],
        _ => [net[cubic_index(1, 0)], net[cubic_index(2, 0)]],
    }
}

/// The apex with the fewest negative or flat original simplices among the volume centroid, the vertex
/// mean and the box centre.
fn choose_apex(positions: &[DVec3], triangles: &[[u32; 3]]) -> DVec3 {
    let mut volume = 0.0;
    let mut moment = DVec3::ZERO;
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let v = a.dot(b.cross(c));
        volume += v;
        moment += (a + b + c) * v;
    }
    let (lo, hi) = positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let mean = positions.iter().copied().sum::<DVec3>() / positions.len().max(1) as f64;
    let mut candidates = vec![];
    if volume.abs() > 0.0 {
        candidates.push(moment / (4.0 * volume));
    }
    candidates.push(mean);
    candidates.push((lo + hi) * 0.5);
    let negatives = |apex: DVec3| {
        triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                orient_sign(a, b, c, apex) <= 0
            })
            .count()
    };
    candidates
        .into_iter()
        .filter(|c| c.is_finite())
        .min_by_key(|&c| negatives(c))
        .unwrap_or(DVec3::ZERO)
}

/// The slab test of a ray against a box.
fn ray_hits_box(ray: &Ray, lo: DVec3, hi: DVec3) -> bool {
    let inv = ray.dir.recip();
    let t1 = (lo - ray.origin) * inv;
    let t2 = (hi - ray.origin) * inv;
    let near = t1.min(t2).max_element();
    let far = t1.max(t2).min_element();
    // NaN (0·∞ on a face) keeps the box: conservative.
    far >= near.max(0.0) && near <= ray.max || far.is_nan() || near.is_nan()
}

/// The most entries of the cube map's or the grid's index: the grids are coarsened past it.
const MAX_INDEX: usize = 1 << 24;

/// Directions from the apex, binned on the six faces of a cube: each cell lists the original
/// simplices whose cone meets it.
#[derive(Clone, Debug)]
struct CubeMap {
    res: usize,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl CubeMap {
    fn new(apex: DVec3, positions: &[DVec3], triangles: &[[u32; 3]], coefficients: &[i8]) -> Self {
        let cells_wanted = (triangles.len() * 8).max(6);
        let mut res =
            (libm::ceil(crate::math::sqrt((cells_wanted / 6) as f64)) as usize).clamp(1, 128);
        // Footprints, coarsened until the index fits in MAX_INDEX entries (a hostile mesh of many
        // nested layers would otherwise list each triangle in thousands of cells).
        let (counts, footprints) = loop {
            let n = 6 * res * res;
            let mut counts = vec![0u32; n + 1];
            let mut footprints: Vec<(u32, usize, [usize; 4])> = Vec::new();
            let mut total = 0usize;
            for (t, tri) in triangles.iter().enumerate() {
                if coefficients[t] == 0 {
                    continue;
                }
                let corners = tri.map(|i| positions[i as usize] - apex);
                for face in 0..6 {
                    if let Some(rect) = footprint(&corners, face, res) {
                        total += (rect[1] - rect[0] + 1) * (rect[3] - rect[2] + 1);
                        footprints.push((t as u32, face, rect));
                    }
                }
            }
            if total > MAX_INDEX && res > 1 {
                res /= 2;
                continue;
            }
            for &(_, face, rect) in &footprints {
                for v in rect[2]..=rect[3] {
                    for u in rect[0]..=rect[1] {
                        counts[(face * res + v) * res + u] += 1;
                    }
                }
            }
            break (counts, footprints);
        };
        let n = 6 * res * res;
        let mut offsets = vec![0u32; n + 1];
        for i in 0..n {
            offsets[i + 1] = offsets[i] + counts[i];
        }
        let mut fill = offsets.clone();
        let mut items = vec![0u32; offsets[n] as usize];
        for (t, face, rect) in footprints {
            for v in rect[2]..=rect[3] {
                for u in rect[0]..=rect[1] {
                    let c = (face * res + v) * res + u;
                    items[fill[c] as usize] = t;
                    fill[c] += 1;
                }
            }
        }
        Self {
            res,
            offsets,
            items,
        }
    }

    /// The simplices listed for the direction `d` (any length; zero reads as `+x`, the direction
    /// the symbolic perturbation moves a query at the apex).
    fn cell(&self, d: DVec3) -> &[u32] {
        let d = if d == DVec3::ZERO { DVec3::X } else { d };
        let abs = d.abs();
        let major = if abs.x >= abs.y && abs.x >= abs.z {
            0
        } else if abs.y >= abs.z {
            1
        } else {
            2
        };
        let m = d[major];
        let face = major * 2 + usize::from(m < 0.0);
        let u = d[(major + 1) % 3] / m.abs();
        let v = d[(major + 2) % 3] / m.abs();
        let r = self.res as f64;
        let iu = (((u + 1.0) * 0.5 * r) as usize).min(self.res - 1);
        let iv = (((v + 1.0) * 0.5 * r) as usize).min(self.res - 1);
        let c = (face * self.res + iv) * self.res + iu;
        &self.items[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }
}

/// The cells `[u0, u1, v0, v1]` of cube face `face` (major axis `face / 2`, positive for even)
/// that the cone over the triangle `corners` (relative to the apex) may meet; `None` if it misses
/// the face. Conservative: the face's pyramid is widened a little before clipping, and the box padded.
fn footprint(corners: &[DVec3; 3], face: usize, res: usize) -> Option<[usize; 4]> {
    let major = face / 2;
    let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
    let (a1, a2) = ((major + 1) % 3, (major + 2) % 3);
    let mut poly = [DVec3::ZERO; 12];
    let mut len = 3;
    poly[..3].copy_from_slice(corners);
    let widen = 1.0 + 1e-9;
    // Clip by sign·x_m·widen ± x_a ≥ 0 for both other axes.
    for (axis, s) in [(a1, 1.0), (a1, -1.0), (a2, 1.0), (a2, -1.0)] {
        let h = |p: DVec3| sign * p[major] * widen + s * p[axis];
        let mut out = [DVec3::ZERO; 12];
        let mut out_len = 0;
        for i in 0..len {
            let (p, q) = (poly[i], poly[(i + 1) % len]);
            let (hp, hq) = (h(p), h(q));
            if hp >= 0.0 && out_len < out.len() {
                out[out_len] = p;
                out_len += 1;
            }
            if (hp >= 0.0) != (hq >= 0.0) && out_len < out.len() {
                let t = hp / (hp - hq);
                out[out_len] = p + (q - p) * t;
                out_len += 1;
            }
        }
        poly = out;
        len = out_len;
        if len == 0 {
            return None;
        }
    }
    let (mut ulo, mut uhi, mut vlo, mut vhi) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in &poly[..len] {
        let m = sign * p[major];
        if m <= 0.0 {
            // A clipped vertex at the apex's plane: the cone reaches the face's rim.
            ulo = -1.0;
            uhi = 1.0;
            vlo = -1.0;
            vhi = 1.0;
            continue;
        }
        let (u, v) = (p[a1] / m, p[a2] / m);
        ulo = ulo.min(u);
        uhi = uhi.max(u);
        vlo = vlo.min(v);
        vhi = vhi.max(v);
    }
    let pad = 1e-7;
    let r = res as f64;
    let cell = |x: f64| (libm::floor((x + 1.0) * 0.5 * r).clamp(0.0, r - 1.0)) as usize;
    Some([
        cell(ulo - pad),
        cell(uhi + pad),
        cell(vlo - pad),
        cell(vhi + pad),
    ])
}

/// A uniform grid over boxes: each cell lists the boxes that overlap it.
#[derive(Clone, Debug)]
struct Grid {
    lo: DVec3,
    hi: DVec3,
    dims: [usize; 3],
    step: DVec3,
    offsets: Vec<u32>,
    items: Vec<u32>,
    boxes: Vec<(DVec3, DVec3)>,
}

impl Grid {
    fn new(boxes: &[(DVec3, DVec3)]) -> Self {
        let (lo, hi) = boxes.iter().fold(
            (DVec3::INFINITY, DVec3::NEG_INFINITY),
            |(lo, hi), &(a, b)| (lo.min(a), hi.max(b)),
        );
        let extent = (hi - lo).max(DVec3::splat(1e-300));
        let target = (boxes.len() * 2).max(1) as f64;
        let mut size =
            libm::cbrt(extent.x * extent.y * extent.z / target).max(extent.max_element() / 256.0);
        // Coarsened until the index fits in MAX_INDEX entries (long slivers span many cells).
        let (dims, step) = loop {
            let dims = [0, 1, 2].map(|a| (libm::ceil(extent[a] / size) as usize).clamp(1, 256));
            let step = extent / DVec3::new(dims[0] as f64, dims[1] as f64, dims[2] as f64);
            let total: usize = boxes
                .iter()
                .map(|&(a, b)| {
                    let cells = ((b - a) / step).floor() + 2.0;
                    (0..3)
                        .map(|k| (cells[k] as usize).min(dims[k]))
                        .product::<usize>()
                })
                .sum();
            if total <= MAX_INDEX || dims == [1, 1, 1] {
                break (dims, step);
            }
            size *= 2.0;
        };
        let index_range = |a: DVec3, b: DVec3| {
            let i0 = ((a - lo) / step).floor();
            let i1 = ((b - lo) / step).floor();
            [0, 1, 2].map(|k| {
                let top = (dims[k] - 1) as f64;
                (
                    i0[k].clamp(0.0, top) as usize,
                    i1[k].clamp(0.0, top) as usize,
                )
            })
        };
        let n = dims[0] * dims[1] * dims[2];
        let mut counts = vec![0u32; n];
        let each = |f: &mut dyn FnMut(usize, usize)| {
            for (t, &(a, b)) in boxes.iter().enumerate() {
                let r = index_range(a, b);
                for z in r[2].0..=r[2].1 {
                    for y in r[1].0..=r[1].1 {
                        for x in r[0].0..=r[0].1 {
                            f(t, (z * dims[1] + y) * dims[0] + x);
                        }
                    }
                }
            }
        };
        each(&mut |_, c| counts[c] += 1);
        let mut offsets = vec![0u32; n + 1];
        for i in 0..n {
            offsets[i + 1] = offsets[i] + counts[i];
        }
        let mut fill = offsets.clone();
        let mut items = vec![0u32; offsets[n] as usize];
        each(&mut |t, c| {
            items[fill[c] as usize] = t as u32;
            fill[c] += 1;
        });
        Self {
            lo,
            hi,
            dims,
            step,
            offsets,
            items,
            boxes: boxes.to_vec(),
        }
    }

    fn items_at(&self, x: usize, y: usize, z: usize) -> &[u32] {
        let c = (z * self.dims[1] + y) * self.dims[0] + x;
        &self.items[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }

    /// The boxes listed for the cell holding `q` (none outside the grid).
    fn cell(&self, q: DVec3) -> &[u32] {
        if !(q.cmpge(self.lo).all() && q.cmple(self.hi).all()) {
            return &[];
        }
        let i = ((q - self.lo) / self.step).floor();
        let [x, y, z] = [0, 1, 2].map(|k| (i[k] as usize).min(self.dims[k] - 1));
        self.items_at(x, y, z)
    }

    /// Calls `visit` with the list of every cell the ray passes through, in order (3D DDA).
    fn walk(&self, ray: &Ray, mut visit: impl FnMut(&[u32])) {
        let inv = ray.dir.recip();
        let t1 = (self.lo - ray.origin) * inv;
        let t2 = (self.hi - ray.origin) * inv;
        let near = t1.min(t2).max_element().max(0.0);
        let far = t1.max(t2).min_element().min(ray.max);
        if near > far || near.is_nan() || far.is_nan() {
            return;
        }
        let start = ray.origin + ray.dir * near;
        let mut cell = [0usize; 3];
        let mut next = [f64::INFINITY; 3];
        let mut delta = [f64::INFINITY; 3];
        let mut stepdir = [0isize; 3];
        for k in 0..3 {
            let top = self.dims[k] - 1;
            let f = libm::floor((start[k] - self.lo[k]) / self.step[k]);
            cell[k] = (f.max(0.0) as usize).min(top);
            let d = ray.dir[k];
            if d > 0.0 {
                stepdir[k] = 1;
                let boundary = self.lo[k] + (cell[k] + 1) as f64 * self.step[k];
                next[k] = near + (boundary - start[k]) / d;
                delta[k] = self.step[k] / d;
            } else if d < 0.0 {
                stepdir[k] = -1;
                let boundary = self.lo[k] + cell[k] as f64 * self.step[k];
                next[k] = near + (boundary - start[k]) / d;
                delta[k] = -self.step[k] / d;
            }
        }
        let max_steps = self.dims[0] + self.dims[1] + self.dims[2] + 3;
        for _ in 0..max_steps {
            visit(self.items_at(cell[0], cell[1], cell[2]));
            let k = if next[0] <= next[1] && next[0] <= next[2] {
                0
            } else if next[1] <= next[2] {
                1
            } else {
                2
            };
            if next[k] > far {
                return;
            }
            let c = cell[k] as isize + stepdir[k];
            if c < 0 || c >= self.dims[k] as isize {
                return;
            }
            cell[k] = c as usize;
            next[k] += delta[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_grid_index_stays_bounded_for_boxes_that_span_everything() {
        // 20 000 boxes across the whole scene would list each in every cell of a fine grid.
        let boxes: Vec<(DVec3, DVec3)> = (0..20_000)
            .map(|i| {
                let t = f64::from(i) / 20_000.0;
                (DVec3::new(0.0, t, 0.0), DVec3::new(1.0, t + 1e-3, 1.0))
            })
            .collect();
        let grid = Grid::new(&boxes);
        assert!(grid.items.len() <= MAX_INDEX, "{}", grid.items.len());
        // Still an index: every box is listed where it is.
        let q = DVec3::new(0.5, 0.25, 0.5);
        assert!(grid.cell(q).contains(&5000));
    }
}
