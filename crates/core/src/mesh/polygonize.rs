//! Marching cubes with face-consistent case handling, chosen for its manifold guarantee.
//!
//! Each cube is handled on its own, from the signs of its corners (inside is `f > 0`):
//!
//! 1. On each of the six faces, marching squares: the zero crossings on the face's edges are joined
//!    in pairs. A face with two diagonal positive corners is ambiguous; the asymptotic decider (the
//!    sign of the bilinear interpolant's saddle, `f00·f11 − f10·f01`) decides whether the positive
//!    corners connect. Both cubes sharing a face see the same four values and decide the same way, so
//!    the surface has no cracks.
//! 2. Every crossing lies on one cube edge, which borders two faces, so the face segments chain into
//!    disjoint closed loops on the cube's boundary.
//! 3. Each loop is filled with a disk: a fan from a corner whose diagonals all pass through the cube's
//!    inside (no diagonal joins two crossings on one face), or, where no corner allows that (only
//!    around ambiguous faces), a fan around a new centre vertex.
//!
//! Why this and not the 256-case table or a dual method: every mesh edge is either a face segment
//! (shared by exactly the two cubes on either side, one triangle each, run in opposite directions
//! because each cube orients the face segment as seen from its own outside) or a diagonal through one
//! cube's inside (two triangles of that cube's disk), so the result is a closed, consistently oriented
//! 2-manifold by construction, with no table to get wrong. Dual methods (surface nets, dual contouring) put one
//! vertex per cube and pinch where a cube holds two sheets. The price, compared with the full MC33
//! case analysis, is that the inside of a cube with two loops is always split (no tunnel through the
//! cube); topology at that scale is below the sampling resolution anyway.
//!
//! Vertices lie on the grid edges, so the caller can put them on `f = 0` by a 1D root search along
//! the edge ([`EdgeRoots`]); the polygonizer walks the grid one z-layer at a time and keeps vertex
//! indices only for two layers of edges.

use alloc::vec;
use alloc::vec::Vec;

use glam::DVec3;

use super::Mesh;

/// A regular grid of samples: sample `(a, b, c)` is at `origin + step · (a, b, c)`, `0 ≤ a < dims[0]`
/// and so on; values are stored with `a` fastest (index `(c·dims[1] + b)·dims[0] + a`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleGrid {
    /// The position of sample `(0, 0, 0)`.
    pub origin: DVec3,
    /// The spacing along each axis.
    pub step: DVec3,
    /// The number of samples along each axis.
    pub dims: [usize; 3],
}

impl SampleGrid {
    /// The position of sample `(a, b, c)`.
    #[must_use]
    pub fn point(&self, a: usize, b: usize, c: usize) -> DVec3 {
        self.origin + self.step * DVec3::new(a as f64, b as f64, c as f64)
    }
}

/// Where the surface crosses a grid edge, and the normal there. The polygonizer asks only about edges
/// whose end values have opposite signs (`f ≤ 0` at one end, `f > 0` at the other).
pub trait EdgeRoots {
    /// The root on the edge from sample `lower` to the next sample along `axis` (0, 1, 2 for x, y, z),
    /// as a fraction `t ∈ [0, 1]` of the edge, and the outward unit normal there (`−∇f/|∇f|`, zero if
    /// unknown); `f0` and `f1` are the end values.
    fn vertex(&mut self, axis: usize, lower: [usize; 3], f0: f64, f1: f64) -> (f64, DVec3);

    /// A vertex and its normal for the middle of a loop that cannot be fanned (rare: only around
    /// ambiguous faces): `mean` is the mean of the loop's vertices and `[lo, hi]` the cube. The
    /// default keeps `mean` with no normal; a field that can be evaluated should move it onto `f = 0`
    /// within the cube.
    fn centre(&mut self, mean: DVec3, lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
        let _ = (lo, hi);
        (mean, DVec3::ZERO)
    }
}

/// Roots by linear interpolation of the end values, and no normals: the plain marching cubes.
#[derive(Clone, Copy, Debug, Default)]
pub struct LinearRoots;

impl EdgeRoots for LinearRoots {
    fn vertex(&mut self, _axis: usize, _lower: [usize; 3], f0: f64, f1: f64) -> (f64, DVec3) {
        (linear_root(f0, f1), DVec3::ZERO)
    }
}

/// `t` where the line through `(0, f0)` and `(1, f1)` crosses zero, clamped to `[0, 1]`.
pub(crate) fn linear_root(f0: f64, f1: f64) -> f64 {
    let t = f0 / (f0 - f1);
    if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.5
    }
}

/// Corner `c` of a cube (bit 0: +x, bit 1: +y, bit 2: +z).
const fn corner_offset(c: usize) -> [usize; 3] {
    [c & 1, (c >> 1) & 1, (c >> 2) & 1]
}

/// The cube edge from corner `c` along `axis` (where `c` has that bit clear): `axis·4 + the other two
/// bits packed`, 0 to 11.
const fn edge_id(c: usize, axis: usize) -> usize {
    let (b, d) = ((axis + 1) % 3, (axis + 2) % 3);
    axis * 4 + ((c >> b) & 1) + 2 * ((c >> d) & 1)
}

/// The four corners of each face in counter-clockwise order seen from outside the cube: face
/// `2·axis + side`. With `(b, d)` the next two axes cyclically (so `b × d = axis`), the +side face runs
/// `(0,0), (1,0), (1,1), (0,1)` in `(b, d)` and the −side face the reverse.
const FACES: [[usize; 4]; 6] = {
    let mut faces = [[0; 4]; 6];
    let mut axis = 0;
    while axis < 3 {
        let (b, d) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut side = 0;
        while side < 2 {
            let base = side << axis;
            let ring = [0, 1 << b, (1 << b) | (1 << d), 1 << d];
            let mut q = 0;
            while q < 4 {
                // The −side is seen from the other way round: reverse the ring, keeping corner 0 first.
                let r = if side == 1 {
                    ring[q]
                } else {
                    ring[(4 - q) % 4]
                };
                faces[2 * axis + side][q] = base | r;
                q += 1;
            }
            side += 1;
        }
        axis += 1;
    }
    faces
};

/// The cube edge between two corners that differ in one bit.
const fn edge_between(p: usize, q: usize) -> usize {
    let diff = p ^ q;
    let axis = if diff == 1 {
        0
    } else if diff == 2 {
        1
    } else {
        2
    };
    edge_id(p & q, axis)
}

/// The faces (bit `2·axis + side`) that cube edge `e` borders.
const fn edge_faces(e: usize) -> u8 {
    let axis = e / 4;
    let (b, d) = ((axis + 1) % 3, (axis + 2) % 3);
    (1 << (2 * b + (e & 1))) | (1 << (2 * d + ((e >> 1) & 1)))
}

/// A corner of the loop `ring` from which a fan has no diagonal between two crossings on one cube
/// face. Such a diagonal would lie in the face, where the neighbouring cube may draw it too, giving
/// an edge with four triangles; diagonals that pass through the cube's inside are this cube's alone.
fn fan_start(ring: &[u8]) -> Option<usize> {
    let k = ring.len();
    if k <= 3 {
        return Some(0);
    }
    (0..k).find(|&s| {
        (2..k - 1)
            .all(|j| edge_faces(ring[s] as usize) & edge_faces(ring[(s + j) % k] as usize) == 0)
    })
}

/// Face segments of a cube as a map `next[edge] = edge` (the loop runs from a crossing to `next`), for
/// corner values `v`. `255` marks an edge without a crossing.
fn cube_loops(v: &[f64; 8], next: &mut [u8; 12]) {
    *next = [255; 12];
    for face in &FACES {
        let inside = face.map(|c| v[c] > 0.0);
        // Edges q → q+1 (ccw) where the sign goes from outside to inside, and inside to outside.
        let mut enter = [0usize; 2];
        let mut leave = [0usize; 2];
        let (mut ne, mut nl) = (0, 0);
        for q in 0..4 {
            let (a, b) = (inside[q], inside[(q + 1) % 4]);
            if !a && b {
                enter[ne] = q;
                ne += 1;
            } else if a && !b {
                leave[nl] = q;
                nl += 1;
            }
        }
        let edge = |q: usize| edge_between(face[q], face[(q + 1) % 4]) as u8;
        match ne {
            1 => next[edge(enter[0]) as usize] = edge(leave[0]),
            2 => {
                // Ambiguous: the positives are on a diagonal. Positive saddle: they connect, and each
                // entry pairs with the exit just before it (around a negative corner); otherwise with
                // the exit just after it (around a positive corner).
                let (p0, p1) = if inside[0] { (0, 2) } else { (1, 3) };
                let saddle =
                    v[face[p0]] * v[face[p1]] - v[face[(p0 + 1) % 4]] * v[face[(p0 + 3) % 4]];
                for &e in &enter {
                    let after = (e + 1) % 4;
                    let l = if saddle > 0.0 { (e + 3) % 4 } else { after };
                    next[edge(e) as usize] = edge(l);
                }
            }
            _ => {}
        }
    }
}

/// Polygonizes the zero set of a sampled field (inside is `f > 0`) into an indexed mesh, with roots
/// and normals from `roots`. The mesh is closed when the samples on the grid's outer faces are all
/// outside (`f ≤ 0`); it is a consistently oriented 2-manifold in any case, with boundary only on the
/// grid's outer faces.
///
/// `values.len()` must be `dims[0]·dims[1]·dims[2]`; a mismatch gives an empty mesh.
#[must_use]
pub fn polygonize<R: EdgeRoots>(grid: &SampleGrid, values: &[f64], roots: &mut R) -> Mesh {
    let [nx, ny, nz] = grid.dims;
    let mut mesh = Mesh::default();
    if nx < 2 || ny < 2 || nz < 2 || values.len() != nx * ny * nz {
        return mesh;
    }
    let layer = nx * ny;
    // Vertex indices of x- and y-edges in the lower and upper sample layer of the current cube layer,
    // and of z-edges between them (`u32::MAX`: none yet).
    let mut xy_lo = vec![u32::MAX; 2 * layer];
    let mut xy_hi = vec![u32::MAX; 2 * layer];
    let mut z_mid = vec![u32::MAX; layer];
    let marcher = Marcher::new();
    let (mut inside, mut rows) = (Vec::new(), Vec::new());
    // The layer of cubes the edge caches are for.
    let mut c = 0;
    crossed_cubes(
        values,
        grid.dims,
        &mut inside,
        &mut rows,
        |[a, b, z], mask| {
            // The caches move up a layer for each layer of cubes passed.
            while c < z {
                core::mem::swap(&mut xy_lo, &mut xy_hi);
                xy_hi.fill(u32::MAX);
                z_mid.fill(u32::MAX);
                c += 1;
            }
            let base = (c * ny + b) * nx + a;
            let corners = || {
                core::array::from_fn(|k| {
                    let [dx, dy, dz] = corner_offset(k);
                    values[base + dz * layer + dy * nx + dx]
                })
            };
            // Vertex of every crossed cube edge, shared through the caches.
            let vertex = |mesh: &mut Mesh, roots: &mut R, axis: usize, lower: [usize; 3]| {
                let slot = lower[1] * nx + lower[0];
                let cache = match axis {
                    0 | 1 => {
                        let cache = if lower[2] == c {
                            &mut xy_lo
                        } else {
                            &mut xy_hi
                        };
                        &mut cache[2 * slot + axis]
                    }
                    _ => &mut z_mid[slot],
                };
                if *cache == u32::MAX {
                    let i0 = (lower[2] * ny + lower[1]) * nx + lower[0];
                    let i1 = i0 + [1, nx, layer][axis];
                    *cache = edge_vertex(grid, mesh, roots, axis, lower, values[i0], values[i1]);
                }
                *cache
            };
            marcher.cube(mask, corners, [a, b, c], grid, &mut mesh, roots, vertex);
        },
    );
    mesh
}

/// Every cube of a box of samples (`dims` per axis, `x` fastest) whose corners are not all of one
/// sign, with its corner mask (bit `k`: corner `k` inside), layer by layer, row by row: a row of
/// cubes between four sample rows all of one sign is skipped whole. `inside` and `rows` are
/// scratch, reused between calls.
fn crossed_cubes(
    values: &[f64],
    [nx, ny, nz]: [usize; 3],
    inside: &mut Vec<u8>,
    rows: &mut Vec<u8>,
    mut cube: impl FnMut([usize; 3], u8),
) {
    inside.clear();
    inside.extend(values.iter().map(|&v| u8::from(v > 0.0)));
    // Each sample row (along x) all outside (0), all inside (1) or mixed (2).
    rows.clear();
    rows.extend(inside.chunks_exact(nx).map(|r| {
        if r.iter().all(|&s| s == r[0]) {
            r[0]
        } else {
            2
        }
    }));
    for c in 0..nz - 1 {
        for b in 0..ny - 1 {
            let r = [
                c * ny + b,
                c * ny + b + 1,
                (c + 1) * ny + b,
                (c + 1) * ny + b + 1,
            ];
            let states = r.map(|i| rows[i]);
            if states.iter().all(|&s| s == states[0] && s != 2) {
                continue;
            }
            let quad = r.map(|i| &inside[i * nx..(i + 1) * nx]);
            // Corner bits of the cube's x = 0 face from column a: y0z0 → 0, y1z0 → 2, y0z1 → 4, y1z1 → 6.
            let column =
                |a: usize| quad[0][a] | quad[1][a] << 2 | quad[2][a] << 4 | quad[3][a] << 6;
            let mut left = column(0);
            for a in 0..nx - 1 {
                let right = column(a + 1);
                let mask = left | right << 1;
                left = right;
                if mask != 0 && mask != 255 {
                    cube([a, b, c], mask);
                }
            }
        }
    }
}

/// A new vertex on the grid edge from sample `lower` along `axis`, whose end values are `f0` and
/// `f1`: its index in `mesh`.
fn edge_vertex<R: EdgeRoots>(
    grid: &SampleGrid,
    mesh: &mut Mesh,
    roots: &mut R,
    axis: usize,
    lower: [usize; 3],
    f0: f64,
    f1: f64,
) -> u32 {
    let (t, normal) = roots.vertex(axis, lower, f0, f1);
    let mut p = grid.point(lower[0], lower[1], lower[2]);
    p[axis] += t * grid.step[axis];
    let id = mesh.positions.len() as u32;
    mesh.positions.push(p);
    mesh.normals.push(normal);
    id
}

/// What a cube's face loops make, worked out once per loop map: its crossed edges (whose
/// vertices are made in the order of the edges) and its loops in the order they are met from edge
/// 0, each a ring of edges with the corner its fan starts from, or none (a centre vertex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Plan {
    /// Bit `e`: edge `e` is crossed.
    edges: u16,
    /// Each loop: where its ring starts in `rings`, its length, its fan's start ([`NO_FAN`]: the
    /// loop gets a centre vertex).
    loops: [[u8; 3]; 12],
    count: u8,
    /// The rings one after another.
    rings: [u8; 12],
}

/// [`Plan::loops`]: a loop no fan fits.
const NO_FAN: u8 = 255;

impl Plan {
    /// The plan of the loop map `next` ([`cube_loops`]).
    fn of(next: &[u8; 12]) -> Self {
        let mut plan = Self {
            edges: 0,
            loops: [[0; 3]; 12],
            count: 0,
            rings: [0; 12],
        };
        for (e, &n) in next.iter().enumerate() {
            if n != 255 {
                plan.edges |= 1 << e;
            }
        }
        let (mut done, mut used) = (0u16, 0usize);
        for start in 0..12 {
            if next[start] == 255 || done & (1 << start) != 0 {
                continue;
            }
            let first = used;
            let mut at = start;
            // Each edge joins one ring at most (`done`), so the rings fit in twelve.
            while done & (1 << at) == 0 {
                done |= 1 << at;
                plan.rings[used] = at as u8;
                used += 1;
                at = next[at] as usize;
                if at >= 12 {
                    break;
                }
            }
            let fan = fan_start(&plan.rings[first..used]).map_or(NO_FAN, |s| s as u8);
            plan.loops[usize::from(plan.count)] = [first as u8, (used - first) as u8, fan];
            plan.count += 1;
        }
        plan
    }
}

/// The half of the polygonizer that sees one cube: its face loops (from a table of the 256 sign
/// patterns, or from the values where a face is ambiguous) filled with disks. The walk over the
/// whole grid ([`polygonize`]) and the walk over blocks of cells ([`polygonize_blocks`]) share it,
/// so a cube gives the same triangles whichever walk meets it.
pub(crate) struct Marcher {
    /// The plan of every corner pattern without an ambiguous face (those depend on the pattern
    /// alone).
    plans: [Plan; 256],
    ambiguous: [bool; 256],
}

impl Marcher {
    pub(crate) fn new() -> Self {
        // The face loops of every corner pattern without an ambiguous face depend on the pattern alone.
        let mut ambiguous = [false; 256];
        let plans = core::array::from_fn(|mask| {
            let v: [f64; 8] = core::array::from_fn(|k| if mask >> k & 1 == 1 { 1.0 } else { -1.0 });
            ambiguous[mask] = FACES.iter().any(|face| {
                let s = face.map(|c| mask >> c & 1);
                s[0] == s[2] && s[1] == s[3] && s[0] != s[1]
            });
            let mut next = [255u8; 12];
            cube_loops(&v, &mut next);
            Plan::of(&next)
        });
        Self { plans, ambiguous }
    }

    /// The triangles of the cube whose lowest sample is `cube`, whose corner `k` is inside where bit
    /// `k` of `mask` is set: `values()` gives the eight corner values (asked for only when a face is
    /// ambiguous), `vertex(mesh, roots, axis, lower)` the index of the vertex on the grid edge from
    /// sample `lower` along `axis` (made on first use, shared after). A loop that cannot be fanned
    /// gets a centre vertex of its own.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(crate) fn cube<R: EdgeRoots>(
        &self,
        mask: u8,
        values: impl FnOnce() -> [f64; 8],
        cube: [usize; 3],
        grid: &SampleGrid,
        mesh: &mut Mesh,
        roots: &mut R,
        mut vertex: impl FnMut(&mut Mesh, &mut R, usize, [usize; 3]) -> u32,
    ) {
        let own;
        let plan = if self.ambiguous[mask as usize] {
            let mut loops = [255u8; 12];
            cube_loops(&values(), &mut loops);
            own = Plan::of(&loops);
            &own
        } else {
            &self.plans[mask as usize]
        };
        let mut ids = [u32::MAX; 12];
        let mut edges = plan.edges;
        while edges != 0 {
            let e = edges.trailing_zeros() as usize;
            edges &= edges - 1;
            let axis = e / 4;
            let (bb, dd) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut lower = cube;
            lower[bb] += e & 1;
            lower[dd] += (e >> 1) & 1;
            ids[e] = vertex(mesh, roots, axis, lower);
        }
        // Each loop as a disk: a fan where one fits, a centre vertex where none does.
        for &[first, k, fan] in &plan.loops[..usize::from(plan.count)] {
            let (first, k) = (usize::from(first), usize::from(k));
            let ring = &plan.rings[first..first + k];
            match (fan != NO_FAN).then_some(usize::from(fan)) {
                Some(s) => {
                    for j in 1..k - 1 {
                        mesh.triangles.push([
                            ids[ring[s] as usize],
                            ids[ring[(s + j) % k] as usize],
                            ids[ring[(s + j + 1) % k] as usize],
                        ]);
                    }
                }
                None => {
                    let mean = ring
                        .iter()
                        .map(|&e| mesh.positions[ids[e as usize] as usize])
                        .sum::<DVec3>()
                        / k as f64;
                    let lo = grid.point(cube[0], cube[1], cube[2]);
                    let (p, normal) = roots.centre(mean, lo, lo + grid.step);
                    let centre = mesh.positions.len() as u32;
                    mesh.positions.push(p);
                    mesh.normals.push(normal);
                    for j in 0..k {
                        mesh.triangles.push([
                            centre,
                            ids[ring[j] as usize],
                            ids[ring[(j + 1) % k] as usize],
                        ]);
                    }
                }
            }
        }
    }
}

/// A box of cells `[lo, lo + size)` of a grid (its samples `lo ..= lo + size`), sampled whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Block {
    pub(crate) lo: [usize; 3],
    pub(crate) size: [usize; 3],
    /// The caller's word about the block (a tree: which pruned program holds in it).
    pub(crate) tag: u32,
}

impl Block {
    /// Its samples along each axis.
    pub(crate) fn samples(&self) -> [usize; 3] {
        self.size.map(|s| s + 1)
    }

    /// Whether sample `s` (of the grid) is on one of the block's faces, shared with whatever is
    /// beside it.
    pub(crate) fn on_face(&self, s: [usize; 3]) -> bool {
        (0..3).any(|k| s[k] == self.lo[k] || s[k] == self.lo[k] + self.size[k])
    }
}

/// Roots for the walk over blocks: told which block the walk is in, and asked for the value of a
/// sample on a block's face that both blocks beside the face must agree on (the four corners of
/// an ambiguous cube face, whose saddle decides how the face's crossings join).
pub(crate) trait BlockRoots: EdgeRoots {
    /// The walk enters `block`.
    fn enter(&mut self, block: &Block) {
        let _ = block;
    }

    /// The value of sample `s`, on a block's face, that every block sees: `value` (the block's
    /// own) where blocks sample the same function.
    fn canonical(&mut self, s: [usize; 3], value: f64) -> f64 {
        let _ = s;
        value
    }

    /// The walk leaves `block`, the mesh made so far `mesh`.
    fn leave(&mut self, block: &Block, mesh: &Mesh) {
        let _ = (block, mesh);
    }
}

/// The key of the grid edge from sample `lower` along `axis`: unique over the grid, so pieces of a
/// mesh made apart weld on it.
fn edge_key(dims: [usize; 3], axis: usize, lower: [usize; 3]) -> u64 {
    (((lower[2] * dims[1] + lower[1]) * dims[0] + lower[0]) * 3 + axis) as u64
}

/// No grid edge: the key of a vertex that is not on one (a loop's centre).
pub(crate) const NO_EDGE: u64 = u64::MAX;

/// Vertex indices by grid edge: open addressing, linear probing, kept at most half full.
struct EdgeMap {
    keys: Vec<u64>,
    ids: Vec<u32>,
    len: usize,
}

impl EdgeMap {
    fn new() -> Self {
        Self {
            keys: vec![NO_EDGE; 1024],
            ids: vec![0; 1024],
            len: 0,
        }
    }

    fn slot(keys: &[u64], key: u64) -> usize {
        let mask = keys.len() - 1;
        let mut i = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 32) as usize & mask;
        while keys[i] != key && keys[i] != NO_EDGE {
            i = (i + 1) & mask;
        }
        i
    }

    /// The index stored for `key`, or the one `make()` gives, stored.
    fn get_or_insert(&mut self, key: u64, make: impl FnOnce() -> u32) -> u32 {
        let i = Self::slot(&self.keys, key);
        if self.keys[i] == key {
            return self.ids[i];
        }
        let id = make();
        self.keys[i] = key;
        self.ids[i] = id;
        self.len += 1;
        if 2 * self.len > self.keys.len() {
            let size = 2 * self.keys.len();
            let old_keys = core::mem::replace(&mut self.keys, vec![NO_EDGE; size]);
            let old_ids = core::mem::replace(&mut self.ids, vec![0; size]);
            for (k, v) in old_keys.into_iter().zip(old_ids) {
                if k != NO_EDGE {
                    let j = Self::slot(&self.keys, k);
                    self.keys[j] = k;
                    self.ids[j] = v;
                }
            }
        }
        id
    }
}

/// The cells of `blocks` alone polygonized, each block's samples given by `sample(block, values)`
/// (`(size + 1)` per axis, `x` fastest, as [`polygonize`] takes them). Cells outside every block
/// must hold no surface. Every vertex comes with the key of its grid edge ([`NO_EDGE`] for a
/// centre or a vertex inside a block, which no other block can have), so meshes of disjoint sets
/// of blocks weld into the mesh of their union ([`weld`]).
///
/// The samples a block shares with its neighbours must be the same values in both, as a function
/// of the sample would give them; then each cube gives what [`polygonize`] gives it.
pub(crate) fn polygonize_blocks<R: BlockRoots>(
    grid: &SampleGrid,
    blocks: &[Block],
    mut sample: impl FnMut(&Block, &mut Vec<f64>),
    roots: &mut R,
    marcher: &Marcher,
) -> (Mesh, Vec<u64>) {
    let mut mesh = Mesh::default();
    let mut keys: Vec<u64> = Vec::new();
    // Edges on a block's faces are shared with its neighbours: their vertices go by grid edge.
    // Edges inside a block are its own: their vertices go by a table of the block's edges, each
    // entry stamped with the block it was made in (so the table is never cleared).
    let mut map = EdgeMap::new();
    let mut own: Vec<(u32, u32)> = Vec::new();
    let mut values = Vec::new();
    let (mut inside, mut rows): (Vec<u8>, Vec<u8>) = (Vec::new(), Vec::new());
    // A block that the surface crosses holds some dozens of vertices and twice as many triangles.
    mesh.positions.reserve(48 * blocks.len());
    mesh.normals.reserve(48 * blocks.len());
    mesh.triangles.reserve(96 * blocks.len());
    let dims = grid.dims;
    for (stamp, block) in blocks.iter().enumerate() {
        let stamp = stamp as u32;
        values.clear();
        sample(block, &mut values);
        roots.enter(block);
        let [sx, sy, sz] = block.samples();
        if values.len() != sx * sy * sz {
            roots.leave(block, &mesh);
            continue;
        }
        if own.len() < 3 * values.len() {
            own.resize(3 * values.len(), (u32::MAX, 0));
        }
        let (row, layer) = (sx, sx * sy);
        let at = |x: usize, y: usize, z: usize| (z * sy + y) * sx + x;
        crossed_cubes(
            &values,
            [sx, sy, sz],
            &mut inside,
            &mut rows,
            |[x, y, z], mask| {
                let base = at(x, y, z);
                let cube = [block.lo[0] + x, block.lo[1] + y, block.lo[2] + z];
                // An ambiguous face is decided by its values: on a block's face, the values
                // the block beside sees too.
                let corners: [f64; 8] = if marcher.ambiguous[mask as usize] {
                    core::array::from_fn(|k| {
                        let [dx, dy, dz] = corner_offset(k);
                        let v = values[base + dz * layer + dy * row + dx];
                        let s = [cube[0] + dx, cube[1] + dy, cube[2] + dz];
                        if block.on_face(s) {
                            roots.canonical(s, v)
                        } else {
                            v
                        }
                    })
                } else {
                    [0.0; 8]
                };
                let corners = || corners;
                let vertex = |mesh: &mut Mesh, roots: &mut R, axis: usize, lower: [usize; 3]| {
                    let l = [0, 1, 2].map(|k| lower[k] - block.lo[k]);
                    let i0 = at(l[0], l[1], l[2]);
                    let i1 = i0 + [1, row, layer][axis];
                    let (f0, f1) = (values[i0], values[i1]);
                    let on_face = (0..3).any(|k| k != axis && (l[k] == 0 || l[k] == block.size[k]));
                    if on_face {
                        map.get_or_insert(edge_key(dims, axis, lower), || {
                            keys.resize(mesh.positions.len(), NO_EDGE);
                            keys.push(edge_key(dims, axis, lower));
                            edge_vertex(grid, mesh, roots, axis, lower, f0, f1)
                        })
                    } else {
                        let entry = &mut own[3 * i0 + axis];
                        if entry.0 != stamp {
                            *entry = (stamp, edge_vertex(grid, mesh, roots, axis, lower, f0, f1));
                        }
                        entry.1
                    }
                };
                marcher.cube(mask, corners, cube, grid, &mut mesh, roots, vertex);
            },
        );
        roots.leave(block, &mesh);
    }
    keys.resize(mesh.positions.len(), NO_EDGE);
    (mesh, keys)
}

/// The mesh of a run of blocks ([`polygonize_blocks`]) split into each block's piece: block `b`
/// made the vertices and triangles below `ends[b]` (vertices, triangles) and above the block
/// before's. Each piece holds the vertices its block made, in order, after those of earlier blocks
/// its triangles use (on the faces between them, keyed by their grid edge); [`weld_kept`] of the
/// pieces in order is the run's mesh.
pub(crate) fn split_run((mesh, keys): &Keyed, ends: &[(usize, usize)]) -> Vec<Keyed> {
    let mut pieces = Vec::with_capacity(ends.len());
    // Where each vertex of the run is in the piece being made (u32::MAX: not in it).
    let mut local = vec![u32::MAX; mesh.positions.len()];
    let (mut v0, mut t0) = (0, 0);
    for &(v1, t1) in ends {
        let (v1, t1) = (
            v1.min(mesh.positions.len()).max(v0),
            t1.min(mesh.triangles.len()).max(t0),
        );
        let mut piece = Mesh::default();
        let mut piece_keys = Vec::new();
        let mut take = |piece: &mut Mesh, piece_keys: &mut Vec<u64>, i: usize| {
            local[i] = piece.positions.len() as u32;
            piece.positions.push(mesh.positions[i]);
            piece
                .normals
                .push(mesh.normals.get(i).copied().unwrap_or(DVec3::ZERO));
            piece_keys.push(keys.get(i).copied().unwrap_or(NO_EDGE));
        };
        // The earlier blocks' vertices the triangles use, in the run's order, then its own.
        let mut earlier: Vec<usize> = mesh.triangles[t0..t1]
            .iter()
            .flatten()
            .map(|&v| v as usize)
            .filter(|&v| v < v0)
            .collect();
        earlier.sort_unstable();
        earlier.dedup();
        for &i in &earlier {
            take(&mut piece, &mut piece_keys, i);
        }
        for i in v0..v1 {
            take(&mut piece, &mut piece_keys, i);
        }
        piece.triangles = mesh.triangles[t0..t1]
            .iter()
            .map(|t| t.map(|v| local.get(v as usize).copied().unwrap_or(u32::MAX)))
            .collect();
        for i in earlier.into_iter().chain(v0..v1) {
            local[i] = u32::MAX;
        }
        pieces.push((piece, piece_keys));
        (v0, t0) = (v1, t1);
    }
    pieces
}

/// One share of a mesh made in parts, on separate threads, workers or machines: share `index` of
/// `count`, a run of consecutive blocks of the cells the mesher samples (in its fixed order, runs of
/// equal length). The [`Piece`]s of all the shares, welded in order ([`Piece::weld`]), are the
/// mesh made whole; their triangles, one after another, are its triangles (on the same vertices,
/// bit for bit, for a Bézier solid; for a tree a vertex two shares have is the same root to within
/// the accuracy asked, each share's from its own block's pruned program).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Share {
    index: usize,
    count: usize,
}

impl Share {
    /// The whole mesh as one share.
    pub const WHOLE: Self = Self { index: 0, count: 1 };

    /// Share `index` of `count`; `None` unless `index < count`.
    #[must_use]
    pub const fn new(index: usize, count: usize) -> Option<Self> {
        if index < count {
            Some(Self { index, count })
        } else {
            None
        }
    }

    /// Which share, from 0.
    #[must_use]
    pub const fn index(self) -> usize {
        self.index
    }

    /// How many shares the mesh is made in.
    #[must_use]
    pub const fn count(self) -> usize {
        self.count
    }

    /// This share's run of `len` items (slices, rows, jobs): runs of `⌈len / count⌉` in order,
    /// the last ones shorter or empty.
    #[must_use]
    pub fn range(self, len: usize) -> core::ops::Range<usize> {
        let run = len.div_ceil(self.count);
        let start = (self.index * run).min(len);
        start..(start + run).min(len)
    }

    /// This share's run of `items` ([`Share::range`]).
    #[cfg(test)]
    pub(crate) fn of<T>(self, items: &[T]) -> &[T] {
        &items[self.range(items.len())]
    }

    /// This share's run of `blocks`, runs of about equal samples (blocks differ in size), so that
    /// shares made side by side end together: share `k` starts at the first block whose samples
    /// before it reach `k / count` of all.
    pub(crate) fn of_blocks(self, blocks: &[Block]) -> &[Block] {
        let samples = |b: &Block| b.size.iter().map(|s| s + 1).product::<usize>();
        let total: usize = blocks.iter().map(samples).sum();
        let start_of = |k: usize| {
            if k == 0 {
                return 0;
            }
            if k >= self.count {
                return blocks.len();
            }
            // The first block at which the samples before it reach k / count of the total.
            let goal = (total as u128 * k as u128).div_ceil(self.count as u128);
            let mut before = 0u128;
            for (i, b) in blocks.iter().enumerate() {
                if before >= goal {
                    return i;
                }
                before += samples(b) as u128;
            }
            blocks.len()
        };
        &blocks[start_of(self.index)..start_of(self.index + 1)]
    }
}

/// A share's mesh ([`Share`]), with the grid edge of each vertex another share may also have
/// ([`Piece::UNSHARED`] for the others), so that pieces weld into the whole mesh exactly.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Piece {
    /// The share's triangles, on its own vertices.
    pub mesh: Mesh,
    /// One key per vertex of `mesh`: its grid edge, or [`Piece::UNSHARED`].
    pub keys: Vec<u64>,
}

impl Piece {
    /// The key of a vertex no other piece has.
    pub const UNSHARED: u64 = NO_EDGE;

    /// The pieces of a mesh's shares, in the order of the shares, joined into the mesh made whole:
    /// a vertex two pieces share (the same key) is kept once, the first piece's.
    #[must_use]
    pub fn weld(pieces: Vec<Self>) -> Mesh {
        weld_keyed(pieces.into_iter().map(|p| (p.mesh, p.keys)).collect()).0
    }
}

/// A mesh of some blocks with the grid edge of each vertex (or [`NO_EDGE`]), as
/// [`polygonize_blocks`] makes it.
pub(crate) type Keyed = (Mesh, Vec<u64>);

/// Meshes of disjoint sets of cells, each with the grid edge of every vertex (from
/// [`polygonize_blocks`]), joined into one: a vertex on an edge two pieces share is kept once, the
/// first piece's. Pieces in the order of their blocks give the mesh of all the blocks in one walk.
#[cfg(test)]
pub(crate) fn weld(pieces: Vec<Keyed>) -> Mesh {
    weld_keyed(pieces).0
}

/// [`weld_keyed`] of pieces kept elsewhere (a cache of a mesh's blocks): the same mesh.
pub(crate) fn weld_kept<'a>(pieces: impl IntoIterator<Item = &'a Keyed>) -> Keyed {
    let (mut mesh, mut kept) = (Mesh::default(), Vec::new());
    let mut map = EdgeMap::new();
    for (piece, keys) in pieces {
        append(&mut mesh, &mut kept, &mut map, piece, keys);
    }
    (mesh, kept)
}

/// Adds `piece` (its vertices keyed by `keys`) to `mesh` (its vertices keyed by `kept`, the
/// shared ones found by `map`): a vertex whose key is there already is that one.
fn append(mesh: &mut Mesh, kept: &mut Vec<u64>, map: &mut EdgeMap, piece: &Mesh, keys: &[u64]) {
    let n = piece.positions.len();
    let mut remap = Vec::with_capacity(n);
    // The piece's vertices from `run` on that are new to the mesh, copied whole when a vertex
    // the mesh has already ends the run (or the piece ends).
    let copy = |mesh: &mut Mesh, kept: &mut Vec<u64>, run: core::ops::Range<usize>| {
        let len = run.len();
        mesh.positions
            .extend_from_slice(&piece.positions[run.clone()]);
        let at = |n: usize| run.start.min(n)..run.end.min(n);
        let normals = &piece.normals[at(piece.normals.len())];
        mesh.normals.extend_from_slice(normals);
        mesh.normals
            .resize(mesh.normals.len() + len - normals.len(), DVec3::ZERO);
        let run_keys = &keys[at(keys.len())];
        kept.extend_from_slice(run_keys);
        kept.resize(kept.len() + len - run_keys.len(), NO_EDGE);
    };
    let (mut run, mut next) = (0, mesh.positions.len() as u32);
    for i in 0..n {
        let k = keys.get(i).copied().unwrap_or(NO_EDGE);
        if k != NO_EDGE {
            let id = map.get_or_insert(k, || next);
            if id != next {
                copy(mesh, kept, run..i);
                run = i + 1;
                remap.push(id);
                continue;
            }
        }
        remap.push(next);
        next += 1;
    }
    copy(mesh, kept, run..n);
    mesh.triangles.extend(
        piece
            .triangles
            .iter()
            .filter(|t| t.iter().all(|&v| (v as usize) < remap.len()))
            .map(|t| t.map(|v| remap[v as usize])),
    );
}

/// [`weld`], with the key of each vertex of the mesh it makes.
pub(crate) fn weld_keyed(pieces: Vec<Keyed>) -> Keyed {
    let mut pieces = pieces.into_iter();
    let Some((mut mesh, mut kept)) = pieces.next() else {
        return (Mesh::default(), Vec::new());
    };
    kept.resize(mesh.positions.len(), NO_EDGE);
    mesh.normals.resize(mesh.positions.len(), DVec3::ZERO);
    if pieces.as_slice().is_empty() {
        // One piece is welded already (the one-thread path costs no table of its keys).
        return (mesh, kept);
    }
    let mut map = EdgeMap::new();
    let (vertices, triangles) = pieces.as_slice().iter().fold((0, 0), |(v, t), (m, _)| {
        (v + m.positions.len(), t + m.triangles.len())
    });
    mesh.positions.reserve(vertices);
    mesh.normals.reserve(vertices);
    mesh.triangles.reserve(triangles);
    kept.reserve(vertices);
    for (i, &k) in kept.iter().enumerate() {
        if k != NO_EDGE {
            map.get_or_insert(k, || i as u32);
        }
    }
    for (piece, keys) in pieces {
        append(&mut mesh, &mut kept, &mut map, &piece, &keys);
    }
    (mesh, kept)
}

/// A weld in progress: pieces added in order make the mesh [`weld_keyed`] makes of them all.
pub(crate) struct Welder {
    welded: Option<Keyed>,
    /// The keyed vertices welded so far, made when the second piece comes.
    map: Option<EdgeMap>,
    /// Pieces still to come, counting the next.
    expected: usize,
}

impl Welder {
    /// A weld of about `count` pieces (room is made for that many of the first one's size).
    pub(crate) fn expecting(count: usize) -> Self {
        Self {
            welded: None,
            map: None,
            expected: count,
        }
    }

    /// The next piece welded on.
    pub(crate) fn add(&mut self, (piece, keys): Keyed) {
        let rest = self.expected.saturating_sub(1);
        self.expected = rest;
        let Some((mesh, kept)) = &mut self.welded else {
            let (mut mesh, mut kept) = (piece, keys);
            let (vertices, triangles) = (mesh.positions.len(), mesh.triangles.len());
            kept.resize(vertices, NO_EDGE);
            mesh.normals.resize(vertices, DVec3::ZERO);
            if rest > 0 {
                mesh.positions.reserve(vertices * rest);
                mesh.normals.reserve(vertices * rest);
                kept.reserve(vertices * rest);
                mesh.triangles.reserve(triangles * rest);
            }
            self.welded = Some((mesh, kept));
            return;
        };
        let map = self.map.get_or_insert_with(|| {
            let mut map = EdgeMap::new();
            for (i, &k) in kept.iter().enumerate() {
                if k != NO_EDGE {
                    map.get_or_insert(k, || i as u32);
                }
            }
            map
        });
        append(mesh, kept, map, &piece, &keys);
    }

    /// The mesh welded, with the key of each vertex.
    pub(crate) fn finish(self) -> Keyed {
        self.welded.unwrap_or_default()
    }
}

/// The pieces `make(0)`, `make(1)`, … `make(count − 1)` welded in order ([`weld_keyed`]),
/// `welded(k)` called on the calling thread as piece `k` is welded on. With the `parallel`
/// feature, on rayon's pool: every thread takes the next piece not yet taken, and the calling
/// thread, between its pieces, welds those that are in, in order, so that the weld runs beside
/// the meshing rather than after it.
pub(crate) fn make_and_weld(
    count: usize,
    make: impl Fn(usize) -> Keyed + Sync,
    mut welded: impl FnMut(usize),
) -> Keyed {
    #[cfg(feature = "parallel")]
    if count > 1 && rayon::current_num_threads() > 1 {
        return make_and_weld_on_pool(count, make, welded);
    }
    let mut welder = Welder::expecting(count);
    for k in 0..count {
        welder.add(make(k));
        welded(k);
    }
    welder.finish()
}

/// [`make_and_weld`] on rayon's pool.
#[cfg(feature = "parallel")]
fn make_and_weld_on_pool(
    count: usize,
    make: impl Fn(usize) -> Keyed + Sync,
    mut welded: impl FnMut(usize),
) -> Keyed {
    use core::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    /// A piece not made yet, made, or lost (its task panicked: the scope passes the panic on).
    enum Slot {
        Waiting,
        Made(Keyed),
        Lost,
    }
    /// Marks its slot lost unless the piece came: dropped when the making ends, however it ends.
    struct Mark<'a>(&'a Mutex<Slot>);
    impl Drop for Mark<'_> {
        fn drop(&mut self) {
            if let Ok(mut slot) = self.0.lock()
                && matches!(*slot, Slot::Waiting)
            {
                *slot = Slot::Lost;
            }
        }
    }
    let slots: Vec<Mutex<Slot>> = (0..count).map(|_| Mutex::new(Slot::Waiting)).collect();
    let next = AtomicUsize::new(0);
    // The next piece no one has taken, made: false when none is left.
    let take = || {
        let k = next.fetch_add(1, Ordering::Relaxed);
        let Some(slot) = slots.get(k) else {
            return false;
        };
        let _mark = Mark(slot);
        let piece = make(k);
        if let Ok(mut slot) = slot.lock() {
            *slot = Slot::Made(piece);
        }
        true
    };
    let mut welder = Welder::expecting(count);
    rayon::in_place_scope(|scope| {
        for _ in 1..rayon::current_num_threads().min(count) {
            scope.spawn(|_| while take() {});
        }
        let mut done = 0;
        while done < count {
            let taken = match slots[done].lock() {
                Ok(mut slot) => core::mem::replace(&mut *slot, Slot::Waiting),
                Err(_) => Slot::Lost,
            };
            match taken {
                Slot::Made(piece) => {
                    welder.add(piece);
                    welded(done);
                    done += 1;
                }
                Slot::Lost => break,
                // Make a piece meanwhile; with none left, let the others finish theirs.
                Slot::Waiting => {
                    if !take() && !matches!(rayon::yield_now(), Some(rayon::Yield::Executed)) {
                        std::thread::yield_now();
                    }
                }
            }
        }
    });
    welder.finish()
}

/// Into how many pieces work on many blocks is cut for rayon's pool: four a thread, to balance
/// the load; one on a pool of one thread (pieces there only cost their welding).
#[cfg(feature = "parallel")]
pub(crate) fn pieces_for_pool() -> usize {
    match rayon::current_num_threads() {
        0 | 1 => 1,
        threads => 4 * threads,
    }
}

/// Into how many pieces [`make_and_weld`] cuts work on many blocks: sixteen a thread, each
/// thread taking the next as it finishes one, so that the threads end together and the weld of
/// the last pieces is short (on two cores, the benchmark volume at 128³: four a thread 1.5× one
/// thread, sixteen 1.8×); one on a pool of one thread.
#[cfg(feature = "parallel")]
pub(crate) fn pieces_taken_in_turn() -> usize {
    match rayon::current_num_threads() {
        0 | 1 => 1,
        threads => 16 * threads,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Rng;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A sign pattern without an ambiguous face makes one plan whatever the values: the table's
    /// plan is the plan of the loops of any values with that pattern; every crossed edge is in
    /// exactly one ring.
    #[test]
    fn the_plan_of_a_pattern_is_the_plan_of_its_values() {
        let marcher = Marcher::new();
        let mut rng = Rng::new(3);
        for mask in 0..256usize {
            let plan = marcher.plans[mask];
            let ringed = plan.loops[..usize::from(plan.count)]
                .iter()
                .flat_map(|&[first, k, _]| {
                    plan.rings[usize::from(first)..usize::from(first) + usize::from(k)].iter()
                })
                .fold(0u16, |seen, &e| {
                    assert_eq!(seen & 1 << e, 0, "mask {mask}: edge {e} twice");
                    seen | 1 << e
                });
            assert_eq!(ringed, plan.edges, "mask {mask}");
            assert_eq!(plan.edges == 0, mask == 0 || mask == 255);
            if marcher.ambiguous[mask] {
                continue;
            }
            for _ in 0..20 {
                let v: [f64; 8] = core::array::from_fn(|k| {
                    let size = rng.range(1e-6, 2.0);
                    if mask >> k & 1 == 1 { size } else { -size }
                });
                let mut next = [255u8; 12];
                cube_loops(&v, &mut next);
                assert_eq!(Plan::of(&next), plan, "mask {mask}, values {v:?}");
            }
        }
    }

    fn sample(dims: [usize; 3], f: impl Fn(DVec3) -> f64) -> (SampleGrid, Vec<f64>) {
        let step = DVec3::splat(1.0)
            / DVec3::new(
                dims[0] as f64 - 1.0,
                dims[1] as f64 - 1.0,
                dims[2] as f64 - 1.0,
            );
        let grid = SampleGrid {
            origin: DVec3::ZERO,
            step,
            dims,
        };
        let mut values = Vec::new();
        for c in 0..dims[2] {
            for b in 0..dims[1] {
                for a in 0..dims[0] {
                    values.push(f(grid.point(a, b, c)));
                }
            }
        }
        (grid, values)
    }

    #[test]
    fn faces_are_counter_clockwise_from_outside() {
        for (i, face) in FACES.iter().enumerate() {
            let (axis, side) = (i / 2, i % 2);
            let p = face.map(|c| {
                let o = corner_offset(c);
                DVec3::new(o[0] as f64, o[1] as f64, o[2] as f64)
            });
            let normal = (p[1] - p[0]).cross(p[2] - p[1]);
            let mut want = DVec3::ZERO;
            want[axis] = if side == 1 { 1.0 } else { -1.0 };
            assert_eq!(normal, want, "face {i}");
        }
    }

    #[test]
    fn every_corner_case_gives_closed_loops() {
        // All 256 sign patterns, with both outcomes of the face decider.
        for mask in 0..256usize {
            for scale in [0.5, 2.0] {
                let v: [f64; 8] =
                    core::array::from_fn(|k| if mask >> k & 1 == 1 { 1.0 } else { -scale });
                let mut next = [255u8; 12];
                cube_loops(&v, &mut next);
                let mut incoming = [0; 12];
                for &n in next.iter().filter(|&&n| n != 255) {
                    incoming[n as usize] += 1;
                }
                for e in 0..12 {
                    let crossed = next[e] != 255;
                    assert_eq!(
                        incoming[e],
                        usize::from(crossed),
                        "mask {mask:#010b} edge {e}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_ball_is_a_closed_sphere_with_its_volume() {
        let r = 0.35;
        let (grid, values) = sample([40, 40, 40], |p| {
            r * r - (p - DVec3::splat(0.5)).length_squared()
        });
        let mesh = polygonize(&grid, &values, &mut LinearRoots);
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), 2);
        let exact = 4.0 / 3.0 * core::f64::consts::PI * r * r * r;
        assert!(
            (mesh.volume() - exact).abs() < 0.01 * exact,
            "{} vs {exact}",
            mesh.volume()
        );
    }

    #[test]
    fn random_fields_give_closed_manifolds() {
        // Noise forces every ambiguous case, many times over; the outer layer is outside.
        let mut rng = Rng::new(50);
        for round in 0..20 {
            let n = 6 + round % 5;
            let dims = [n, n + 1, n + 2];
            let mut values: Vec<f64> = (0..dims[0] * dims[1] * dims[2])
                .map(|_| rng.range(-1.0, 1.0))
                .collect();
            for c in 0..dims[2] {
                for b in 0..dims[1] {
                    for a in 0..dims[0] {
                        if a == 0
                            || b == 0
                            || c == 0
                            || a == dims[0] - 1
                            || b == dims[1] - 1
                            || c == dims[2] - 1
                        {
                            values[(c * dims[1] + b) * dims[0] + a] = -1.0;
                        }
                    }
                }
            }
            let grid = SampleGrid {
                origin: DVec3::ZERO,
                step: DVec3::ONE,
                dims,
            };
            let mesh = polygonize(&grid, &values, &mut LinearRoots);
            assert!(mesh.triangle_count() > 0);
            mesh.check_closed_manifold().unwrap();
            // A closed oriented surface bounds a positive volume.
            assert!(mesh.volume() > 0.0);
        }
    }

    #[test]
    fn bad_sizes_give_an_empty_mesh() {
        let grid = SampleGrid {
            origin: DVec3::ZERO,
            step: DVec3::ONE,
            dims: [3, 3, 3],
        };
        assert_eq!(
            polygonize(&grid, &[1.0; 26], &mut LinearRoots),
            Mesh::default()
        );
        let flat = SampleGrid {
            dims: [1, 3, 3],
            ..grid
        };
        assert_eq!(
            polygonize(&flat, &[1.0; 9], &mut LinearRoots),
            Mesh::default()
        );
    }

    #[test]
    fn shares_cover_the_items_once_in_order() {
        assert_eq!(Share::new(2, 2), None);
        assert_eq!(Share::new(0, 0), None);
        for len in [0, 1, 5, 16, 17] {
            let items: Vec<usize> = (0..len).collect();
            for count in 1..=9 {
                let joined: Vec<usize> = (0..count)
                    .flat_map(|k| Share::new(k, count).unwrap().of(&items).to_vec())
                    .collect();
                assert_eq!(joined, items, "{len} items in {count} shares");
            }
        }
        assert_eq!(Share::WHOLE.of(&[1, 2, 3]), &[1, 2, 3]);
    }

    #[test]
    fn shares_of_blocks_cover_them_once_in_order_with_even_samples() {
        let mut rng = Rng::new(5);
        for len in [0, 1, 2, 9, 100] {
            let blocks: Vec<Block> = (0..len)
                .map(|i| Block {
                    lo: [i, 0, 0],
                    size: [rng.int(1, 8), rng.int(1, 8), rng.int(1, 8)],
                    tag: 0,
                })
                .collect();
            let samples = |b: &[Block]| -> usize {
                b.iter()
                    .map(|b| b.size.iter().map(|s| s + 1).product::<usize>())
                    .sum()
            };
            let (total, largest) = (samples(&blocks), 9 * 9 * 9);
            for count in 1..=7 {
                let runs: Vec<&[Block]> = (0..count)
                    .map(|k| Share::new(k, count).unwrap().of_blocks(&blocks))
                    .collect();
                let joined: Vec<Block> = runs.iter().flat_map(|r| r.to_vec()).collect();
                assert_eq!(joined, blocks, "{len} blocks in {count} shares");
                for run in &runs {
                    assert!(
                        samples(run) <= total / count + largest,
                        "{len} blocks in {count} shares: {} of {total}",
                        samples(run)
                    );
                }
            }
        }
    }

    /// Pieces handed in from outside (a worker's, a file's) weld without a panic however they are
    /// made: missing keys or normals, triangles past their vertices.
    #[test]
    fn malformed_pieces_weld_without_panicking() {
        let mesh = |n: usize, t: [u32; 3]| Mesh {
            positions: (0..n).map(|i| DVec3::splat(i as f64)).collect(),
            normals: Vec::new(),
            triangles: vec![t],
        };
        let welded = Piece::weld(vec![
            Piece {
                mesh: mesh(3, [0, 1, 2]),
                keys: vec![7],
            },
            Piece {
                mesh: mesh(3, [0, 1, 9]),
                keys: vec![7, 8],
            },
            Piece {
                mesh: mesh(3, [0, 1, 2]),
                keys: Vec::new(),
            },
        ]);
        assert_eq!(welded.positions.len(), 3 + 2 + 3);
        assert_eq!(welded.normals.len(), welded.positions.len());
        assert_eq!(welded.triangles, vec![[0, 1, 2], [5, 6, 7]]);
    }
}
