//! What the modeler draws of ESC solids and their Booleans: the paper's point meshes (Figs. 12–19)
//! and a closed surface of a Boolean result whose vertices are the exact crossings of grid edges
//! with the PN surfaces.

use alloc::collections::BinaryHeap;
use alloc::vec;
use alloc::vec::Vec;
use core::cmp::Reverse;

use glam::DVec3;

use super::bool::Expr;
use super::chain::{EscSolid, Stats};
use super::pn::{CubicNet, PnSurface};
use super::ray::bisect;
use crate::mesh::{EdgeRoots, Mesh, SampleGrid, polygonize};

/// The largest grid of a point mesh or a Boolean surface, per axis.
pub const MAX_RESOLUTION: usize = 160;

/// A Boolean expression over ESC solids.
#[derive(Clone, Debug)]
pub struct Boolean {
    /// The solids, numbered as the expression uses them.
    pub solids: Vec<EscSolid>,
    /// The expression; a solid number past the end reads as empty.
    pub expr: Expr,
}

/// A regular grid of points classified against a Boolean (the paper's point-mesh view).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointMesh {
    /// Points drawn plain: for one binary operation, those of the partial chain that the final
    /// term keeps (the final result less the marked points); otherwise the final result.
    pub inside: Vec<DVec3>,
    /// Points of the partial chain that the final term removes (drawn red in the paper's
    /// intermediate figures); empty unless the expression is one binary operation.
    pub marked: Vec<DVec3>,
    /// The spacing of the grid.
    pub step: f64,
}

impl Boolean {
    /// `f(q)` of the expression's chain: 1 in the result, 0 outside.
    #[must_use]
    pub fn value(&self, q: DVec3, stats: &mut Stats) -> i32 {
        self.expr.value(&mut |i| {
            self.solids
                .get(i)
                .map_or(0, |s| i32::from(s.value(q, stats) == 1))
        })
    }

    /// The box of all the solids (empty, with infinite corners, when there are none).
    #[must_use]
    pub fn scene_bounds(&self) -> (DVec3, DVec3) {
        self.solids
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), s| {
                let (a, b) = s.bounds();
                (lo.min(a), hi.max(b))
            })
    }

    /// Whether the result is bounded: far from every solid each solid is out, so the result holds
    /// the points far away exactly when the expression of all solids out is 1. A complement alone,
    /// or a union with one, is not: its [`Boolean::surface`] is the solids' surface turned inside
    /// out (a negative volume), not a solid to export; intersect it with a bounded solid first.
    #[must_use]
    pub fn is_bounded(&self) -> bool {
        self.expr.value(&mut |_| 0) == 0
    }

    /// A box holding the result: unions and differences of the operands' boxes, intersections of
    /// them; a complement is bounded by all the solids' box.
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let all = self.scene_bounds();
        let (lo, hi) = bound(&self.expr, &self.solids, all);
        if lo.cmple(hi).all() {
            (lo, hi)
        } else {
            // An empty result: a point-sized box at the scene's centre.
            let c = (all.0 + all.1) * 0.5;
            (c, c)
        }
    }

    /// The grid of `res` points along the longest side of the scene (both operands' boxes), and
    /// which of them are in the result; for one binary operation also the marked points of the
    /// paper's intermediate picture ([`super::bool::Op::partial`]).
    #[must_use]
    pub fn point_mesh(&self, res: usize) -> PointMesh {
        let res = res.clamp(2, MAX_RESOLUTION);
        let all = self.scene_bounds();
        let mut out = PointMesh::default();
        if !all.0.is_finite() {
            return out;
        }
        let grid = grid_over(all, res, 0);
        out.step = grid.step.x;
        let mut stats = Stats::default();
        for c in 0..grid.dims[2] {
            for b in 0..grid.dims[1] {
                for a in 0..grid.dims[0] {
                    let q = grid.point(a, b, c);
                    if let Expr::Binary(op, x, y) = &self.expr {
                        let sub = |e: &Expr, stats: &mut Stats| {
                            e.value(&mut |i| {
                                self.solids
                                    .get(i)
                                    .map_or(0, |s| i32::from(s.value(q, stats) == 1))
                            })
                        };
                        let (f1, f2) = (sub(x, &mut stats), sub(y, &mut stats));
                        let (partial, marked) = op.partial(f1, f2);
                        if marked {
                            out.marked.push(q);
                        } else if partial {
                            out.inside.push(q);
                        }
                    } else if self.value(q, &mut stats) == 1 {
                        out.inside.push(q);
                    }
                }
            }
        }
        out
    }

    /// The closed surface of the result on a grid of `res` cells along the longest side of its
    /// box: marching cubes on the membership, with each vertex where the grid edge crosses the
    /// PN surface that changes the result (an exact segment–patch intersection) and the normal of
    /// that PN patch there. Where a crossing cannot be told (a seam), the vertex is found by
    /// bisection of the membership instead.
    ///
    /// A solid is asked at the first sample of each row along x, and at each sample whose grid
    /// edge from the previous one its PN surface may cross (the edge meets the box of a piece of
    /// a patch, the patches split until each piece spans at most a cell); every other sample is
    /// in the solid exactly when the previous one is. The work follows the surface's area in cells
    /// rather than the grid's volume: a coarse mesh with rounded edges (a cube with a crease angle
    /// of 180°) has thick free-form cells, where most samples of the grid would each need a
    /// ray–patch intersection.
    ///
    /// A few samples fall in parts of the result thinner than a cell (where two surfaces meet at
    /// a small angle) with no neighbour on their side. Where the solids, asked on a finer lattice
    /// around such a sample, show its part joined to more of the result (or of the outside), it
    /// takes its neighbours' side: the thin part is below the grid's resolution, and the surface
    /// gets no bubble that the result does not have.
    #[must_use]
    pub fn surface(&self, res: usize) -> Mesh {
        self.surface_in_steps(res, |_, _| {})
    }

    /// [`Boolean::surface`], calling `progress(done, total)` after each layer of samples and at
    /// the end (`done == total`).
    #[must_use]
    pub fn surface_in_steps(&self, res: usize, mut progress: impl FnMut(usize, usize)) -> Mesh {
        self.surface_reporting(res, &mut progress)
    }

    /// [`Boolean::surface_in_steps`] compiled once, here, whatever the caller's `progress`.
    fn surface_reporting(&self, res: usize, progress: &mut dyn FnMut(usize, usize)) -> Mesh {
        let res = res.clamp(2, MAX_RESOLUTION);
        let (lo, hi) = self.bounds();
        if !(lo.is_finite() && hi.is_finite()) || lo == hi {
            progress(1, 1);
            return Mesh::default();
        }
        let parts = self.far_parts();
        if parts.len() < 2 {
            return self.surface_in((lo, hi), res, progress);
        }
        // Parts far apart, each on a grid of its own (one grid over all of them gave each part
        // less than a cell): the meshes side by side, the progress over the parts.
        const STEPS: usize = 1000;
        let count = parts.len();
        let mut mesh = Mesh::default();
        for (k, part) in parts.into_iter().enumerate() {
            let piece = self.surface_in(part, res, &mut |done, total| {
                progress(k * STEPS + done * STEPS / total.max(1), count * STEPS);
            });
            mesh.append(&piece);
        }
        progress(count * STEPS, count * STEPS);
        mesh
    }

    /// The surface within the box `(lo, hi)`, which holds a part of the result and no other's.
    fn surface_in(
        &self,
        (lo, hi): (DVec3, DVec3),
        res: usize,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Mesh {
        let grid = grid_over((lo, hi), res, 1);
        let [nx, ny, nz] = grid.dims;
        let steps = nz + 1;
        let mut stats = Stats::default();
        let crossable: Vec<Vec<bool>> = self
            .solids
            .iter()
            .map(|s| crossable_edges(s.surface(), &grid))
            .collect();
        // Each solid's membership at each sample, then the result's.
        let mut members = vec![vec![0u8; nx * ny * nz]; self.solids.len()];
        let mut values = vec![0.0; nx * ny * nz];
        for c in 0..nz {
            for b in 0..ny {
                for a in 0..nx {
                    let i = (c * ny + b) * nx + a;
                    let q = grid.point(a, b, c);
                    let solids = self.solids.iter().zip(members.iter_mut());
                    for ((s, m), crossable) in solids.zip(&crossable) {
                        m[i] = if a > 0 && !crossable[i] {
                            m[i - 1]
                        } else {
                            u8::from(s.value(q, &mut stats) == 1)
                        };
                    }
                    let v = self
                        .expr
                        .value(&mut |s| members.get(s).map_or(0, |m| i32::from(m[i])));
                    values[i] = if v == 1 { 1.0 } else { -1.0 };
                }
            }
            progress(c + 1, steps);
        }
        self.settle_specks(&grid, &mut values, &mut stats);
        let mut roots = Crossings {
            boolean: self,
            grid: &grid,
            members: &members,
            hits: Vec::new(),
            state: vec![0; self.solids.len()],
        };
        let mesh = polygonize(&grid, &values, &mut roots);
        progress(steps, steps);
        mesh
    }
}

/// The most samples of a speck that [`Boolean::settle_specks`] looks at.
const MAX_SPECK: usize = 8;

/// The subdivisions of a cell tried in turn by [`Boolean::holds_piece`], and the fewest points of
/// that fine lattice a piece must hold to count as seen at that level.
const SPECK_LEVELS: [usize; 4] = [8, 16, 32, 64];
const SPECK_RESOLVED: usize = 64;

/// The most points of the fine lattice around one speck.
const SPECK_LATTICE: usize = 1 << 22;

impl Boolean {
    /// Settles the specks among the samples: sets of at most [`MAX_SPECK`] samples, joined along
    /// grid edges, whose every other neighbour along a grid edge is on the other side of the
    /// result's boundary (a sample in the result with all six neighbours outside, or the reverse).
    ///
    /// Marching cubes draws each speck as a closed surface of its own, a bubble smaller than a
    /// cell or two. The solids classify such samples right (ray parity on the PN surfaces agrees):
    /// they fall in the result's thin parts, where two surfaces meet at a small angle (the wedge
    /// between them stays thinner than a cell for some way from their intersection curve, and
    /// only here and there does a sample fall in it). Such a wedge is part of a larger piece of the
    /// result, joined to it between the samples, and its speck would add a component that the
    /// result does not have. So a speck is kept only where
    /// the solids confirm a piece of the result of its own there ([`Boolean::holds_piece`]);
    /// otherwise its samples take their neighbours' side: the thin part is below the grid's
    /// resolution, and left out as in the rest of the wedge.
    fn settle_specks(&self, grid: &SampleGrid, values: &mut [f64], stats: &mut Stats) {
        let [nx, ny, nz] = grid.dims;
        if nx < 3 || ny < 3 || nz < 3 {
            return;
        }
        let layer = nx * ny;
        let inside = |i: usize| values[i] > 0.0;
        let border = |i: usize| {
            let (a, b, c) = (i % nx, (i / nx) % ny, i / layer);
            a == 0 || b == 0 || c == 0 || a == nx - 1 || b == ny - 1 || c == nz - 1
        };
        let neighbours = |i: usize| [i - 1, i + 1, i - nx, i + nx, i - layer, i + layer];
        // Samples already in a speck or in a set found to be larger.
        let mut seen = vec![false; values.len()];
        let mut specks: Vec<(bool, Vec<usize>)> = Vec::new();
        let mut queue: Vec<usize> = Vec::with_capacity(MAX_SPECK + 1);
        for c in 1..nz - 1 {
            for b in 1..ny - 1 {
                let row = (c * ny + b) * nx;
                let first = inside(row);
                // A speck's row holds samples on both sides (its own and its neighbours along x).
                if (row + 1..row + nx).all(|i| inside(i) == first) {
                    continue;
                }
                for i in row + 1..row + nx - 1 {
                    // Every speck has a sample whose neighbour along x is on the other side.
                    let side = inside(i);
                    if (inside(i - 1) == side && inside(i + 1) == side) || seen[i] {
                        continue;
                    }
                    // The samples joined to i on its side, until more than a speck's.
                    queue.clear();
                    queue.push(i);
                    seen[i] = true;
                    let mut large = false;
                    let mut k = 0;
                    'fill: while k < queue.len() {
                        let s = queue[k];
                        k += 1;
                        for j in neighbours(s) {
                            if inside(j) != side || queue.contains(&j) {
                                continue;
                            }
                            // A sample seen before and not in this set is in a larger one (a
                            // speck's samples join none outside it).
                            if seen[j] || border(j) || queue.len() == MAX_SPECK {
                                large = true;
                                break 'fill;
                            }
                            seen[j] = true;
                            queue.push(j);
                        }
                    }
                    if !large {
                        specks.push((side, queue.clone()));
                    }
                }
            }
        }
        for (side, speck) in specks {
            if !self.holds_piece(grid, &speck, side, values, stats) {
                for i in speck {
                    values[i] = -values[i];
                }
            }
        }
    }

    /// Whether the solids confirm that the samples `speck` (on the side `inside` of the result)
    /// lie in a piece of that side of their own, within the cells around them: the piece is
    /// filled on a finer lattice over those cells ([`SPECK_LEVELS`]), and it is confirmed when
    /// the fill reaches neither the cells' outer faces nor another sample of the grid. A piece of
    /// too few lattice points is filled again on a finer one (a wedge thinner than the lattice's
    /// spacing falls apart into single points); past the finest, or where a finer lattice would
    /// be too large ([`SPECK_LATTICE`]), the speck is kept.
    fn holds_piece(
        &self,
        grid: &SampleGrid,
        speck: &[usize],
        inside: bool,
        values: &[f64],
        stats: &mut Stats,
    ) -> bool {
        let [nx, ny, _] = grid.dims;
        let coords = |i: usize| [i % nx, (i / nx) % ny, i / (nx * ny)];
        let (mut lo, mut hi) = ([usize::MAX; 3], [0; 3]);
        for &i in speck {
            let p = coords(i);
            for k in 0..3 {
                lo[k] = lo[k].min(p[k] - 1);
                hi[k] = hi[k].max(p[k] + 1);
            }
        }
        for level in SPECK_LEVELS {
            let dims = [0, 1, 2].map(|k| (hi[k] - lo[k]) * level + 1);
            let total = dims[0] * dims[1] * dims[2];
            if total > SPECK_LATTICE {
                return true;
            }
            // 0: not yet asked; 1: on the speck's side; 2: on the other.
            let mut state = vec![0u8; total];
            let index = |f: [usize; 3]| (f[2] * dims[1] + f[1]) * dims[0] + f[0];
            // Filled first nearest the outer faces, so that a piece joined to them is found
            // after few points.
            let margin = |f: [usize; 3]| (0..3).map(|a| f[a].min(dims[a] - 1 - f[a])).min();
            let mut queue: BinaryHeap<Reverse<(usize, [usize; 3])>> = BinaryHeap::new();
            for &i in speck {
                let p = coords(i);
                let f = [0, 1, 2].map(|k| (p[k] - lo[k]) * level);
                state[index(f)] = 1;
                queue.push(Reverse((margin(f).unwrap_or(0), f)));
            }
            let mut filled = queue.len();
            while let Some(Reverse((_, f))) = queue.pop() {
                for d in 0..27 {
                    if d == 13 {
                        continue;
                    }
                    let step = [d % 3, (d / 3) % 3, d / 9];
                    let mut g = [0; 3];
                    let mut off = false;
                    for a in 0..3 {
                        // f + step − 1, within the lattice.
                        match (f[a] + step[a]).checked_sub(1) {
                            Some(x) if x < dims[a] => g[a] = x,
                            _ => off = true,
                        }
                    }
                    if off || state[index(g)] != 0 {
                        continue;
                    }
                    let sample = g.iter().all(|&x| x % level == 0);
                    let here = if sample {
                        let [a, b, c] = [0, 1, 2].map(|a| lo[a] + g[a] / level);
                        values[(c * grid.dims[1] + b) * nx + a] > 0.0
                    } else {
                        let t = DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64) / level as f64;
                        let q = grid.point(lo[0], lo[1], lo[2]) + grid.step * t;
                        self.value(q, stats) == 1
                    };
                    if here != inside {
                        state[index(g)] = 2;
                        continue;
                    }
                    // Joined to the cells' outer faces, or to another sample: not a piece of
                    // its own.
                    let m = margin(g).unwrap_or(0);
                    if sample || m == 0 {
                        return false;
                    }
                    state[index(g)] = 1;
                    filled += 1;
                    queue.push(Reverse((m, g)));
                }
            }
            if filled >= SPECK_RESOLVED {
                return true;
            }
        }
        true
    }
}

/// Which grid edges along x the PN surface `pn` may cross, each listed at its upper sample
/// `(a, b, c)` (the edge from `(a − 1, b, c)`; `false` for `a = 0`). The patches are split in
/// halves (newest vertex bisection) until each piece's control net spans at most a cell, and an
/// edge is listed if the box of a piece's net meets it: every piece lies in its net's convex hull,
/// so an edge left out crosses no patch. Pieces outside the grid are dropped; past a budget of
/// pieces (a surface of very many large patches folded through the grid) every edge is listed.
fn crossable_edges(pn: &PnSurface, grid: &SampleGrid) -> Vec<bool> {
    let [nx, ny, nz] = grid.dims;
    let n = nx * ny * nz;
    let mut crossable = vec![false; n];
    let step = grid.step.max_element();
    let top = grid.point(nx - 1, ny - 1, nz - 1);
    let mut marker = Marker {
        grid,
        crossable: &mut crossable,
        step,
        // A hair past the grid's box, so that rounding never drops a piece on its faces.
        lo: grid.origin - DVec3::splat(step * 1e-6),
        hi: top + DVec3::splat(step * 1e-6),
        // Pieces grow as the square of the resolution and samples as its cube: a cube's surface
        // that fills a grid of 24 cells a side takes 1.4 pieces a sample, one of 160 cells 0.3.
        budget: 4 * n + 64 * pn.patches.len(),
    };
    for net in &pn.patches {
        if !marker.mark(net, 0) {
            return vec![true; n];
        }
    }
    crossable
}

/// The state of [`crossable_edges`].
struct Marker<'a> {
    grid: &'a SampleGrid,
    crossable: &'a mut [bool],
    step: f64,
    lo: DVec3,
    hi: DVec3,
    /// Pieces left to look at.
    budget: usize,
}

impl Marker<'_> {
    /// Lists the edges that the piece `net`, `depth` splits down, may cross; `false` when the
    /// budget is spent.
    fn mark(&mut self, net: &CubicNet, depth: u32) -> bool {
        if self.budget == 0 {
            return false;
        }
        self.budget -= 1;
        let (lo, hi) = net
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        if lo.cmpgt(self.hi).any() || hi.cmplt(self.lo).any() {
            return true;
        }
        if (hi - lo).max_element() > self.step && depth < MAX_SPLITS {
            let (first, second) = bisect(net);
            return self.mark(&first, depth + 1) && self.mark(&second, depth + 1);
        }
        // The grid edges along x that the padded box meets, each listed at its upper end: at
        // samples (a, b, c) with x_(a−1) ≤ hi.x, x_a ≥ lo.x, lo.y ≤ y_b ≤ hi.y, lo.z ≤ z_c ≤ hi.z.
        let pad = DVec3::splat(self.step * 1e-6);
        let g = self.grid;
        let lo = ((lo - pad - g.origin) / g.step).ceil();
        let hi = ((hi + pad - g.origin) / g.step).floor();
        let range = |from: f64, to: f64, least: usize, k: usize| {
            let top = (g.dims[k] - 1) as f64;
            (from.max(least as f64), to.min(top))
        };
        let (x0, x1) = range(lo.x, hi.x + 1.0, 1, 0);
        let (y0, y1) = range(lo.y, hi.y, 0, 1);
        let (z0, z1) = range(lo.z, hi.z, 0, 2);
        if x0 > x1 || y0 > y1 || z0 > z1 {
            return true;
        }
        let (x0, x1) = (x0 as usize, x1 as usize);
        for z in z0 as usize..=z1 as usize {
            for y in y0 as usize..=y1 as usize {
                let row = (z * g.dims[1] + y) * g.dims[0];
                self.crossable[row + x0..=row + x1].fill(true);
            }
        }
        true
    }
}

/// The most splits of a patch by [`crossable_edges`]: a piece this far down lists the edges its
/// box meets, however large.
const MAX_SPLITS: u32 = 48;

impl Boolean {
    /// The result's boundary drawn from the solids' own PN surfaces: each patch tessellated into
    /// `level²` triangles (1 to 32), kept where the result changes across it (the expression with
    /// the solid inside differs from it with the solid outside, the other solids as they are at the
    /// point), turned over where the result lies on the solid's outside (the wall a difference
    /// cuts), and trimmed along the other solids' surfaces by bisection in the patch's parameters.
    /// The pieces of different solids meet along the intersection curves without sharing vertices:
    /// a picture of the exact boundary, not a closed mesh (see [`Boolean::surface`] for that).
    #[must_use]
    pub fn trimmed_surface(&self, level: usize) -> Mesh {
        let level = level.clamp(1, 32);
        let mut mesh = Mesh::default();
        let mut stats = Stats::default();
        for (i, solid) in self.solids.iter().enumerate() {
            let pn = solid.surface();
            // +1: kept as it is; −1: kept turned over; 0: not on the result's boundary.
            let mut state = |q: DVec3| -> i8 {
                // The other solids' values at q, each asked once and only if the expression needs
                // it (-1: not yet asked).
                let mut others = vec![-1i32; self.solids.len()];
                let mut with = |v: i32| {
                    self.expr.value(&mut |j| {
                        if j == i {
                            return v;
                        }
                        match others.get(j) {
                            Some(&k) if k >= 0 => k,
                            Some(_) => {
                                let k = i32::from(self.solids[j].value(q, &mut stats) == 1);
                                others[j] = k;
                                k
                            }
                            None => 0,
                        }
                    })
                };
                match (with(1), with(0)) {
                    (1, 0) => 1,
                    (0, 1) => -1,
                    _ => 0,
                }
            };
            for t in 0..pn.patches.len() {
                let net = &pn.patches[t];
                let at = |b: DVec3| super::pn::eval_cubic(net, b);
                // The parameter grid: row r (v = r/l), column c (w = c/l).
                let l = level;
                let bary = |r: usize, c: usize| {
                    let (v, w) = (r as f64 / l as f64, c as f64 / l as f64);
                    DVec3::new((1.0 - v - w).max(0.0), v, w)
                };
                let index = |r: usize, c: usize| crate::triangular::net_index(l, r, c);
                let mut states = Vec::with_capacity((l + 1) * (l + 2) / 2);
                for r in 0..=l {
                    for c in 0..=l - r {
                        states.push(state(at(bary(r, c))));
                    }
                }
                let mut emit = |corners: [(usize, usize); 3]| {
                    let b = corners.map(|(r, c)| bary(r, c));
                    let st = corners.map(|(r, c)| states[index(r, c)]);
                    for keep in [1i8, -1] {
                        if !st.contains(&keep) {
                            continue;
                        }
                        // The part of the sub-triangle where the state is `keep`: corners in it,
                        // and on each edge that leaves it the point where the state changes.
                        let mut poly: Vec<DVec3> = Vec::with_capacity(4);
                        for k in 0..3 {
                            let (b0, b1) = (b[k], b[(k + 1) % 3]);
                            let (s0, s1) = (st[k], st[(k + 1) % 3]);
                            if s0 == keep {
                                poly.push(b0);
                            }
                            if (s0 == keep) != (s1 == keep) {
                                // Bisection along the edge in the parameters, to 2⁻¹⁴ of it.
                                let (mut lo, mut hi) = (0.0, 1.0);
                                for _ in 0..14 {
                                    let m = 0.5 * (lo + hi);
                                    let inside = state(at(b0.lerp(b1, m))) == keep;
                                    if inside == (s0 == keep) {
                                        lo = m;
                                    } else {
                                        hi = m;
                                    }
                                }
                                poly.push(b0.lerp(b1, 0.5 * (lo + hi)));
                            }
                        }
                        for k in 1..poly.len().saturating_sub(1) {
                            let tri = [poly[0], poly[k], poly[k + 1]];
                            let tri = if keep > 0 {
                                tri
                            } else {
                                [tri[0], tri[2], tri[1]]
                            };
                            let base = mesh.positions.len() as u32;
                            for q in tri {
                                mesh.positions.push(at(q));
                                mesh.normals.push(pn.normal(t, q) * f64::from(keep));
                            }
                            mesh.triangles.push([base, base + 1, base + 2]);
                        }
                    }
                };
                for r in 0..l {
                    for c in 0..l - r {
                        emit([(r, c), (r + 1, c), (r, c + 1)]);
                        if c + 1 < l - r {
                            emit([(r + 1, c), (r + 1, c + 1), (r, c + 1)]);
                        }
                    }
                }
            }
        }
        mesh
    }
}

/// The box of an expression's result, within `all`.
fn bound(expr: &Expr, solids: &[EscSolid], all: (DVec3, DVec3)) -> (DVec3, DVec3) {
    match expr {
        Expr::Solid(i) => solids
            .get(*i)
            .map_or((DVec3::INFINITY, DVec3::NEG_INFINITY), EscSolid::bounds),
        Expr::Complement(_) => all,
        Expr::Binary(op, a, b) => {
            let (a0, a1) = bound(a, solids, all);
            let (b0, b1) = bound(b, solids, all);
            match op {
                super::bool::Op::Union => (a0.min(b0), a1.max(b1)),
                super::bool::Op::Intersection => (a0.max(b0), a1.min(b1)),
                super::bool::Op::Difference => (a0, a1),
            }
        }
    }
}

/// A sample grid over `(lo, hi)` with `res` cells along the longest side and `pad` extra cells on
/// every side.
fn grid_over((lo, hi): (DVec3, DVec3), res: usize, pad: usize) -> SampleGrid {
    let extent = (hi - lo).max(DVec3::splat(1e-12));
    let step = extent.max_element() / res as f64;
    let dims = [0, 1, 2].map(|k| (libm::ceil(extent[k] / step) as usize).max(1) + 1 + 2 * pad);
    // Shifted by odd fractions of a step, so that grid lines miss the planes of symmetry that
    // meshes' edges often lie in (a crossing on a seam between patches cannot be told exactly).
    let shift = if pad > 0 {
        DVec3::new(0.0123, 0.0271, 0.0417) * step
    } else {
        DVec3::ZERO
    };
    let origin = lo - DVec3::splat(step * pad as f64) - shift;
    SampleGrid {
        origin,
        step: DVec3::splat(step),
        dims,
    }
}

/// Exact edge crossings for [`polygonize`].
struct Crossings<'a> {
    boolean: &'a Boolean,
    grid: &'a SampleGrid,
    members: &'a [Vec<u8>],
    hits: Vec<(f64, u32, DVec3, i8)>,
    state: Vec<i32>,
}

impl Crossings<'_> {
    fn result(&self) -> i32 {
        self.boolean
            .expr
            .value(&mut |s| self.state.get(s).copied().unwrap_or(0))
    }

    /// The first crossing along the segment where the result changes: `(t, normal)`.
    fn exact(&mut self, p0: DVec3, p1: DVec3, index: usize) -> Option<(f64, DVec3)> {
        let len = (p1 - p0).length();
        let mut all: Vec<(f64, usize, u32, DVec3)> = Vec::new();
        for (s, solid) in self.boolean.solids.iter().enumerate() {
            self.hits.clear();
            solid.segment_hits(p0, p1, &mut self.hits).ok()?;
            all.extend(self.hits.iter().map(|&(l, t, b, _)| (l, s, t, b)));
        }
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (s, m) in self.members.iter().enumerate() {
            self.state[s] = i32::from(m[index]);
        }
        let start = self.result();
        for &(lambda, s, t, b) in &all {
            self.state[s] = 1 - self.state[s];
            let r = self.result();
            if r != start {
                let normal = self.boolean.solids[s].surface().normal(t as usize, b);
                // Outward from the result: along the edge if the result is left there.
                let along = (p1 - p0) / len;
                let normal = if (normal.dot(along) > 0.0) == (start == 1) {
                    normal
                } else {
                    -normal
                };
                return Some(((lambda / len).clamp(0.0, 1.0), normal));
            }
        }
        None
    }
}

impl EdgeRoots for Crossings<'_> {
    fn vertex(&mut self, axis: usize, lower: [usize; 3], f0: f64, _f1: f64) -> (f64, DVec3) {
        let p0 = self.grid.point(lower[0], lower[1], lower[2]);
        let mut p1 = p0;
        p1[axis] += self.grid.step[axis];
        let [nx, ny, _] = self.grid.dims;
        let index = (lower[2] * ny + lower[1]) * nx + lower[0];
        if let Some(found) = self.exact(p0, p1, index) {
            return found;
        }

        // Bisection of the membership.
        let mut stats = Stats::default();
        let inside0 = f0 > 0.0;
        let (mut a, mut b) = (0.0, 1.0);
        for _ in 0..40 {
            let m = 0.5 * (a + b);
            let inside = self.boolean.value(p0.lerp(p1, m), &mut stats) == 1;
            if inside == inside0 {
                a = m;
            } else {
                b = m;
            }
        }
        (0.5 * (a + b), DVec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::esc::bool::Op;
    use crate::esc::examples::Example;
    use crate::esc::pn::DEFAULT_CREASE_ANGLE;
    use alloc::format;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn scene(op: Op) -> Boolean {
        let a = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
        let mut torus = Example::Torus.mesh();
        for p in &mut torus.positions {
            p.z += 0.4;
        }
        let b = EscSolid::new(&torus).expect("valid");
        Boolean {
            solids: vec![a, b],
            expr: Expr::binary(op, Expr::Solid(0), Expr::Solid(1)),
        }
    }

    #[test]
    fn boolean_surfaces_are_closed_with_vertices_on_the_boundary() {
        for op in Op::ALL {
            let boolean = scene(op);
            let mesh = boolean.surface(20);
            assert!(mesh.triangles.len() > 200, "{op}");
            mesh.check_closed_manifold().expect("closed");
            assert!(mesh.volume() > 0.0, "{op}: outward");
            let mut stats = Stats::default();
            let mut exact = 0;
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                if *n == DVec3::ZERO {
                    continue;
                }
                exact += 1;
                // Just inside along the normal is in the result, just outside is not.
                let h = 1e-4;
                assert_eq!(boolean.value(*p - *n * h, &mut stats), 1, "{op} {p}");
                assert_eq!(boolean.value(*p + *n * h, &mut stats), 0, "{op} {p}");
            }
            assert!(
                exact * 10 > mesh.positions.len() * 9,
                "{op}: most vertices exact"
            );
        }
    }

    #[test]
    fn surfaces_of_solids_with_sharp_edges_are_closed_and_flat_on_the_faces() {
        let boolean = imported_cube_minus_octahedron(DEFAULT_CREASE_ANGLE);
        let mesh = boolean.surface(24);
        mesh.check_closed_manifold().expect("closed");
        assert!(mesh.volume() > 0.0);
        let mut stats = Stats::default();
        let mut on_cube = 0;
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            if *n == DVec3::ZERO {
                continue;
            }
            let h = 1e-4;
            assert_eq!(boolean.value(*p - *n * h, &mut stats), 1, "{p}");
            assert_eq!(boolean.value(*p + *n * h, &mut stats), 0, "{p}");
            // On the cube's faces the normal is the face's: the cube stays flat.
            if (p.abs().max_element() - 1.0).abs() < 1e-12 {
                assert!((n.abs().max_element() - 1.0).abs() < 1e-12, "{p} {n}");
                on_cube += 1;
            }
        }
        assert!(on_cube > 100, "{on_cube}");
        // The octahedron's faces, x + y + z = 1.4 and the like, are flat too.
        for p in &mesh.positions {
            assert!(
                p.abs().element_sum() >= 1.4 - 1e-9,
                "{p} inside the octahedron"
            );
        }
    }

    #[test]
    fn trimmed_surfaces_lie_on_the_boundary_of_the_result() {
        for op in Op::ALL {
            // A torus that crosses the sphere steeply (the default scene's meets it at a shallow
            // angle, along a band where the two surfaces stay within h of each other).
            let mut boolean = scene(op);
            let mut torus = Example::Torus.mesh();
            for p in &mut torus.positions {
                *p += DVec3::new(0.6, 0.1, 0.05);
            }
            boolean.solids[1] = EscSolid::new(&torus).expect("valid");
            let mesh = boolean.trimmed_surface(4);
            assert!(mesh.triangles.len() > 1000, "{op}");
            let mut stats = Stats::default();
            let mut checked = 0;
            for (p, n) in mesh.positions.iter().zip(&mesh.normals).step_by(7) {
                // Just inside along the normal is in the result and just outside is not, except
                // at vertices within h of the trimming curves, where a step of h can cross the
                // other solid.
                let h = 1e-3;
                let (a, b) = (
                    boolean.value(*p - *n * h, &mut stats),
                    boolean.value(*p + *n * h, &mut stats),
                );
                if (a, b) == (1, 0) {
                    checked += 1;
                }
            }
            let total = mesh.positions.len().div_ceil(7);
            assert!(checked * 100 >= total * 97, "{op}: {checked} of {total}");
            // Oriented outward: the pieces of a union enclose a positive volume.
            if op == Op::Union {
                assert!(mesh.volume() > 0.0);
            }
        }
    }

    /// A cube and an octahedron that cuts off its corners, read from OBJ text as an import is:
    /// few, large triangles with sharp edges. With the crease angle 180 the edges are rounded and
    /// the free-form cells are thick; with the default they stay sharp and the cells flat.
    fn imported_cube_minus_octahedron(crease_angle: f64) -> Boolean {
        let cube = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\n\
                    v -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
                    f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        let octahedron = "v 1.4 0 0\nv -1.4 0 0\nv 0 1.4 0\nv 0 -1.4 0\nv 0 0 1.4\nv 0 0 -1.4\n\
                          f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
        let solid = |text: &str| {
            let mesh = crate::mesh::read(text.as_bytes()).expect("a closed mesh");
            EscSolid::with_crease_angle(&mesh, crease_angle).expect("valid")
        };
        Boolean {
            solids: vec![solid(cube), solid(octahedron)],
            expr: Expr::binary(Op::Difference, Expr::Solid(0), Expr::Solid(1)),
        }
    }

    #[test]
    fn surfaces_ask_the_solids_near_their_surfaces_and_come_out_as_if_asked_everywhere() {
        for (boolean, res) in [
            (imported_cube_minus_octahedron(180.0), 24),
            (imported_cube_minus_octahedron(DEFAULT_CREASE_ANGLE), 24),
            (scene(Op::Difference), 16),
        ] {
            let mesh = boolean.surface(res);
            assert!(mesh.triangles.len() > 1000);
            // Every solid asked at every sample, as the surface was made before it asked only
            // near the solids' surfaces: the same mesh, bit for bit.
            let grid = grid_over(boolean.bounds(), res, 1);
            let [nx, ny, nz] = grid.dims;
            let n = nx * ny * nz;
            let mut stats = Stats::default();
            let mut members = vec![vec![0u8; n]; boolean.solids.len()];
            let mut values = vec![0.0; n];
            for c in 0..nz {
                for b in 0..ny {
                    for a in 0..nx {
                        let i = (c * ny + b) * nx + a;
                        let q = grid.point(a, b, c);
                        for (s, m) in boolean.solids.iter().zip(members.iter_mut()) {
                            m[i] = u8::from(s.value(q, &mut stats) == 1);
                        }
                        let v = boolean.expr.value(&mut |s| i32::from(members[s][i]));
                        values[i] = if v == 1 { 1.0 } else { -1.0 };
                    }
                }
            }
            boolean.settle_specks(&grid, &mut values, &mut stats);
            // The edges left out of a solid's list join samples alike for that solid, and they
            // are most of the edges.
            for (solid, m) in boolean.solids.iter().zip(&members) {
                let crossable = crossable_edges(solid.surface(), &grid);
                let listed = crossable.iter().filter(|&&x| x).count();
                assert!(listed * 4 < n, "{listed} of {n} edges listed");
                for i in 0..n {
                    if i % nx > 0 && !crossable[i] {
                        assert_eq!(m[i], m[i - 1], "sample {i}");
                    }
                }
            }
            let mut roots = Crossings {
                boolean: &boolean,
                grid: &grid,
                members: &members,
                hits: Vec::new(),
                state: vec![0; boolean.solids.len()],
            };
            assert_eq!(mesh, polygonize(&grid, &values, &mut roots));
        }
    }

    /// The connected components of a mesh (triangles joined by shared vertices).
    fn components(mesh: &Mesh) -> usize {
        let mut parent: Vec<usize> = (0..mesh.positions.len()).collect();
        fn root(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        for t in &mesh.triangles {
            let a = root(&mut parent, t[0] as usize);
            for &v in &t[1..] {
                let b = root(&mut parent, v as usize);
                parent[b] = a;
            }
        }
        let mut roots: Vec<usize> = mesh
            .triangles
            .iter()
            .map(|t| root(&mut parent, t[0] as usize))
            .collect();
        roots.sort_unstable();
        roots.dedup();
        roots.len()
    }

    /// The built-in solids `a` and `b`, `b` moved by `offset`, under `op`.
    fn pair(a: Example, op: Op, b: Example, offset: DVec3) -> Boolean {
        let mut mesh = b.mesh();
        for p in &mut mesh.positions {
            *p += offset;
        }
        Boolean {
            solids: vec![
                EscSolid::new(&a.mesh()).expect("valid"),
                EscSolid::new(&mesh).expect("valid"),
            ],
            expr: Expr::binary(op, Expr::Solid(0), Expr::Solid(1)),
        }
    }

    /// The Euler characteristic of the result's boundary, independently of the grid: each
    /// solid's PN surface tessellated finely (edges a few thousandths of the unit long), welded,
    /// and cut down to the vertices where the result changes across it (as
    /// [`Boolean::trimmed_surface`] keeps them) with the edges and triangles between them. The
    /// boundary is those parts glued along closed intersection curves, whose Euler
    /// characteristic is 0, so the parts' characteristics add up.
    fn tessellated_boundary_euler(boolean: &Boolean) -> i64 {
        let mut stats = Stats::default();
        let mut total = 0;
        for (i, solid) in boolean.solids.iter().enumerate() {
            let level = libm::ceil(libm::sqrt(200_000.0 / solid.triangles().len() as f64));
            let fine = solid.surface().tessellate(level as usize);
            let mut ids = alloc::collections::BTreeMap::new();
            let mut kept = Vec::new();
            let weld: Vec<usize> = fine
                .positions
                .iter()
                .map(|&p| {
                    let key = [p.x, p.y, p.z].map(|x| libm::round(x * 1e9) as i64);
                    *ids.entry(key).or_insert_with(|| {
                        let mut changes = |v: i32| {
                            boolean.expr.value(&mut |j| {
                                if j == i {
                                    v
                                } else {
                                    i32::from(boolean.solids[j].value(p, &mut stats) == 1)
                                }
                            })
                        };
                        kept.push(changes(1) != changes(0));
                        kept.len() - 1
                    })
                })
                .collect();
            let mut edges = Vec::new();
            let mut faces = 0;
            for t in &fine.triangles {
                let t = t.map(|v| weld[v as usize]);
                for e in 0..3 {
                    let (a, b) = (t[e], t[(e + 1) % 3]);
                    if kept[a] && kept[b] {
                        edges.push((a.min(b), a.max(b)));
                    }
                }
                faces += i64::from(t.iter().all(|&v| kept[v]));
            }
            edges.sort_unstable();
            edges.dedup();
            let vertices = kept.iter().filter(|&&k| k).count();
            total += vertices as i64 - edges.len() as i64 + faces;
        }
        total
    }

    #[test]
    fn boolean_surfaces_have_the_components_and_euler_characteristic_of_the_result() {
        // The torus is the ring of radius 1 in the plane z = 0 swept by a tube of radius 0.4
        // (from 0.6 to 1.4 from the z axis); the blob's radius is between 0.6 and 1.4, the
        // icosphere's 1. Each expected Euler characteristic is also that of the boundary found
        // from fine tessellations of the PN surfaces, apart from the grid.
        let cases = [
            // The ring moved 0.3 along x leaves the blob altogether on the +x side (its tube
            // reaches 1.7) and runs through it elsewhere with part of its tube outside all the
            // way round: the difference is the blob with an open groove along an arc, one piece
            // without a handle. On the −x side the blob almost closes over the tube, and where
            // its surface grazes the tube the wedge between them is thinner than a cell: samples
            // in it used to come out as bubbles of their own (11 at 64 cells).
            (
                Example::Blob,
                Op::Difference,
                DVec3::new(0.3, 0.0, 0.0),
                1,
                2,
            ),
            // The page's default scene: the ring raised by 0.35 cuts a groove into the blob.
            (
                Example::Blob,
                Op::Difference,
                DVec3::new(0.0, 0.0, 0.35),
                1,
                2,
            ),
            // The arc of the ring outside the blob is a handle on it.
            (Example::Blob, Op::Union, DVec3::new(0.3, 0.0, 0.0), 1, 0),
            // The ring's hole is within the blob (radius at least 0.6): the union is a ball.
            (Example::Blob, Op::Union, DVec3::ZERO, 1, 2),
            // The arc of the ring inside the blob: a bent rod.
            (
                Example::Blob,
                Op::Intersection,
                DVec3::new(0.3, 0.0, 0.0),
                1,
                2,
            ),
            // The ring's part within radius 1: a thinner ring.
            (Example::Icosphere, Op::Intersection, DVec3::ZERO, 1, 0),
            // The ball less a groove all around it, its two halves joined within radius 0.6.
            (Example::Icosphere, Op::Difference, DVec3::ZERO, 1, 2),
        ];
        for (a, op, offset, parts, euler) in cases {
            let boolean = pair(a, op, Example::Torus, offset);
            assert_eq!(tessellated_boundary_euler(&boolean), euler, "{a:?} {op}");
            for res in [40, 64] {
                let mesh = boolean.surface(res);
                let case = format!("{a:?} {op} torus moved by {offset} at {res}");
                mesh.check_closed_manifold().expect(&case);
                assert!(mesh.volume() > 0.0, "{case}: outward");
                assert_eq!(components(&mesh), parts, "{case}");
                assert_eq!(mesh.euler_characteristic(), euler, "{case}");
            }
        }
    }

    #[test]
    fn surfaces_keep_pieces_smaller_than_a_cell_that_the_result_has() {
        // A ball and a tiny ball (a third of a cell across) around a sample of the grid, away
        // from it (union) or inside it (difference: a tiny cavity): the only sample of the tiny
        // ball, or of the cavity, is a speck that the solids confirm, so it stays a component.
        let res = 32;
        let ball = Example::Icosphere.mesh();
        let solid = EscSolid::new(&ball).expect("valid");
        let grid = grid_over(solid.bounds(), res, 1);
        for (op, at) in [
            (Op::Union, DVec3::splat(0.8)),
            (Op::Difference, DVec3::new(0.3, -0.2, 0.1)),
        ] {
            let g = ((at - grid.origin) / grid.step).round();
            let centre = grid.point(g.x as usize, g.y as usize, g.z as usize);
            let mut tiny = crate::esc::examples::icosphere(2);
            for p in &mut tiny.positions {
                *p = centre + *p * (grid.step.x / 6.0);
            }
            let boolean = Boolean {
                solids: vec![solid.clone(), EscSolid::new(&tiny).expect("valid")],
                expr: Expr::binary(op, Expr::Solid(0), Expr::Solid(1)),
            };
            assert_eq!(boolean.bounds(), solid.bounds(), "the same grid");
            let mesh = boolean.surface(res);
            mesh.check_closed_manifold().expect("closed");
            assert_eq!(components(&mesh), 2, "{op}");
            assert_eq!(mesh.euler_characteristic(), 4, "{op}");
            // The speck's surface: eight triangles around the centre.
            let near = mesh
                .triangles
                .iter()
                .filter(|t| {
                    t.iter()
                        .all(|&v| (mesh.positions[v as usize] - centre).length() < grid.step.x)
                })
                .count();
            assert_eq!(near, 8, "{op}");
        }
    }

    #[test]
    fn surfaces_report_their_progress_layer_by_layer() {
        let boolean = imported_cube_minus_octahedron(180.0);
        let mut steps = Vec::new();
        let mesh = boolean.surface_in_steps(12, |done, total| steps.push((done, total)));
        assert_eq!(mesh, boolean.surface(12));
        let total = steps[0].1;
        assert!(total > 12, "{steps:?}");
        assert_eq!(steps, (1..=total).map(|d| (d, total)).collect::<Vec<_>>());
    }

    #[test]
    fn point_meshes_mark_what_the_last_term_removes() {
        let union = scene(Op::Union).point_mesh(16);
        let inter = scene(Op::Intersection).point_mesh(16);
        // The union's marked points (counted twice) are the intersection's points.
        assert_eq!(union.marked.len(), inter.inside.len());
        assert!(!inter.inside.is_empty());
        let diff = scene(Op::Difference).point_mesh(16);
        // A − B: marked are A ∩ B, kept are A − B; together they are A.
        let a = Boolean {
            solids: scene(Op::Union).solids,
            expr: Expr::Solid(0),
        }
        .point_mesh(16);
        assert_eq!(diff.marked.len() + diff.inside.len(), a.inside.len());
    }
}
