//! Polygonizing a [`Solid3`]: sample `f` on a grid one half cell past the box on every side (so the
//! outer samples are strictly outside and the mesh is closed), march the cubes, then put each vertex
//! on `f = 0` by a root search along its grid edge, where the volume reduces to a Bézier curve.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;
#[cfg(test)]
use glam::DVec4;

use super::Mesh;
use super::adaptive::{self, AdaptiveStats};
use super::polygonize::{
    Block, BlockRoots, EdgeRoots, Keyed, LinearRoots, Marcher, Piece, SampleGrid, Share,
    linear_root, make_and_weld, polygonize, polygonize_blocks,
};
use crate::bernstein::{MAX_DEGREE, basis, basis_and_derivative, casteljau_level};
use crate::inverse::{Forward, solve_jac};
use crate::math::illinois;
use crate::rfunc::{clip_with_gradient, clip3};
use crate::tensor::other_axes;
use crate::{Solid3, Volume};

/// The most cells along the longest side of the box.
pub const MAX_RESOLUTION: usize = 512;

/// Why a solid could not be polygonized.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// The resolution is 0 or above [`MAX_RESOLUTION`].
    Resolution {
        /// The resolution given.
        got: usize,
    },
    /// The accuracy is not a positive finite number.
    Accuracy,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Resolution { got } => {
                write!(f, "resolution {got} is outside 1..={MAX_RESOLUTION}")
            }
            Self::Accuracy => f.write_str("the accuracy must be a positive finite number"),
        }
    }
}

impl core::error::Error for MeshError {}

impl Solid3 {
    /// The sample grid for polygonizing at `resolution` cells along the box's longest side (fewer,
    /// proportionally, along the others, so cells are near cubes), with one extra sample half a cell
    /// outside the box at each end of every axis.
    ///
    /// # Errors
    ///
    /// [`MeshError::Resolution`] for 0 or more than [`MAX_RESOLUTION`].
    pub fn mesh_grid(&self, resolution: usize) -> Result<SampleGrid, MeshError> {
        if resolution == 0 || resolution > MAX_RESOLUTION {
            return Err(MeshError::Resolution { got: resolution });
        }
        let (min, max) = self.domain();
        let (min, max) = crate::math::sampling_box(min.to_array(), max.to_array());
        let (min, max) = (DVec3::from_array(min), DVec3::from_array(max));
        let size = max - min;
        let cell = size.max_element() / resolution as f64;
        let cells = (size / cell)
            .ceil()
            .max(DVec3::ONE)
            .min(DVec3::splat(resolution as f64));
        let step = size / cells;
        Ok(SampleGrid {
            origin: min - step * 0.5,
            step,
            dims: cells.to_array().map(|c| c as usize + 2),
        })
    }

    /// The closed, outward-oriented triangle mesh of the solid's boundary at `resolution` cells along
    /// the longest side of the box: vertices on `f = 0` to within `accuracy` (in `f`), normals `−∇f`.
    ///
    /// The grid is sampled with `S_ξ` alone inside the box and with `f` on the outer samples: inside
    /// the box `F_s > 0`, where `S_ξ & F_s` has the sign of `S_ξ`, so the cubes see the same inside and
    /// outside as with `f`, for the cost of the polynomial; each vertex is then found on `f = 0` itself.
    ///
    /// # Errors
    ///
    /// [`MeshError`] for a resolution out of range or a bad accuracy.
    ///
    /// A space mapping that is certified injective is polygonized in parameter space (the regular
    /// solid of the same `S_ξ` on the unit cube, at `resolution` cells per axis) and its vertices
    /// mapped forward through `(S_x, S_y, S_z)`, normals through `J^{-T}`: the image of the boundary
    /// is the boundary. Any other space mapping (it may fold) samples `f` itself, the largest clipped
    /// `S_ξ` over the preimages, on the grid over its bounds, with vertices interpolated linearly.
    pub fn polygonize(&self, resolution: usize, accuracy: f64) -> Result<Mesh, MeshError> {
        self.polygonize_in_steps(resolution, accuracy, |_, _| {})
    }

    /// [`Self::polygonize`], calling `progress(done, total)` on the way and at the end (`done ==
    /// total`): a net that folds (whose samples each need the inverse map, seconds at a fine
    /// resolution) reports each layer of samples along z, the others only their end.
    ///
    /// # Errors
    ///
    /// As [`Self::polygonize`].
    pub fn polygonize_in_steps(
        &self,
        resolution: usize,
        accuracy: f64,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<Mesh, MeshError> {
        self.polygonize_reporting(resolution, accuracy, &mut progress)
    }

    /// [`Self::polygonize_in_steps`] compiled once, here, whatever the caller's `progress`.
    fn polygonize_reporting(
        &self,
        resolution: usize,
        accuracy: f64,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Mesh, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        let mesh = match self.inverse() {
            None => self.polygonize_regular(resolution, accuracy),
            Some(map) if map.injective() => self.polygonize_forward(resolution, accuracy),
            Some(_) => self.polygonize_sampled(resolution, progress),
        }?;
        progress(1, 1);
        Ok(mesh)
    }

    fn polygonize_forward(&self, resolution: usize, accuracy: f64) -> Result<Mesh, MeshError> {
        self.polygonize_sheets(resolution, accuracy)
    }

    /// The parameter-space mesh (the regular solid of the same `S_ξ` on the unit cube, `resolution`
    /// cells per axis) mapped forward through `(S_x, S_y, S_z)`, whatever the map. For a regular grid
    /// or a map certified injective this is [`Self::polygonize`]'s mesh; where the net folds it also
    /// holds the boundaries of sheets that lie inside others (where `f`, the max over preimages, is
    /// decided by another sheet), and it costs no inverse map: a live preview of a folded net draws it.
    ///
    /// # Errors
    ///
    /// [`MeshError`] for a resolution out of range or a bad accuracy.
    pub fn polygonize_sheets(&self, resolution: usize, accuracy: f64) -> Result<Mesh, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        if self.inverse().is_none() {
            return self.polygonize_regular(resolution, accuracy);
        }
        let mut mesh = self
            .in_parameter_space()
            .polygonize_regular(resolution, accuracy)?;
        self.map_forward(&mut mesh);
        Ok(mesh)
    }

    /// [`Self::polygonize_sheets`] made in parts: the piece of `share` ([`Piece::weld`] of all the
    /// shares' pieces, in order, is that mesh).
    ///
    /// # Errors
    ///
    /// As [`Self::polygonize_sheets`].
    pub fn polygonize_sheets_share(
        &self,
        resolution: usize,
        accuracy: f64,
        share: Share,
    ) -> Result<Piece, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        if self.inverse().is_none() {
            return self.piece_regular(resolution, accuracy, share);
        }
        let mut piece = self
            .in_parameter_space()
            .piece_regular(resolution, accuracy, share)?;
        self.map_forward(&mut piece.mesh);
        Ok(piece)
    }

    /// [`Self::polygonize`] made in parts: the piece of `share` ([`Piece::weld`] of all the
    /// shares' pieces, in order, is that mesh, and their triangles one after another are its
    /// triangles). A net that may fold is sampled whole by the first share (the others are empty).
    ///
    /// # Errors
    ///
    /// As [`Self::polygonize`].
    pub fn polygonize_share(
        &self,
        resolution: usize,
        accuracy: f64,
        share: Share,
    ) -> Result<Piece, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        match self.inverse() {
            None => self.piece_regular(resolution, accuracy, share),
            Some(map) if map.injective() => {
                self.polygonize_sheets_share(resolution, accuracy, share)
            }
            Some(_) => {
                let mesh = if share.index() == 0 {
                    self.polygonize_sampled(resolution, &mut |_, _| {})?
                } else {
                    self.mesh_grid(resolution)?;
                    Mesh::default()
                };
                let keys = vec![Piece::UNSHARED; mesh.positions.len()];
                Ok(Piece { mesh, keys })
            }
        }
    }

    /// A parameter-space mesh's vertices mapped forward through `(S_x, S_y, S_z)`, normals through
    /// `J^{-T}`, triangles turned over where the map reverses orientation.
    fn map_forward(&self, mesh: &mut Mesh) {
        let net = self.net();
        for (p, n) in mesh.positions.iter_mut().zip(&mut mesh.normals) {
            let e = net.forward(p.to_array());
            *p = DVec3::from_array(e.x);
            let jt: [[f64; 3]; 3] = core::array::from_fn(|c| core::array::from_fn(|r| e.jac[r][c]));
            let normal = solve_jac(&jt, n.to_array()).map_or(DVec3::ZERO, DVec3::from_array);
            *n = normal.normalize_or_zero();
        }
        // An orientation-reversing map (a net turned inside out) reverses every triangle.
        let e = net.forward([0.5; 3]);
        let [a, b, c] = e.jac.map(DVec3::from_array);
        if a.dot(b.cross(c)) < 0.0 {
            for t in &mut mesh.triangles {
                t.swap(1, 2);
            }
        }
    }

    fn polygonize_sampled(
        &self,
        resolution: usize,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Mesh, MeshError> {
        let grid = self.mesh_grid(resolution)?;
        let axis = |a: usize| -> Vec<f64> {
            (0..grid.dims[a])
                .map(|i| grid.origin[a] + grid.step[a] * i as f64)
                .collect()
        };
        // Each layer along z reported; the last step is the mesh's, after the layers.
        let values = self.f_grid_in_steps([&axis(0), &axis(1), &axis(2)], |done, total| {
            progress(done, total + 1);
        });
        let mut mesh = polygonize(&grid, &values, &mut LinearRoots);
        mesh.normals = mesh
            .positions
            .iter()
            .map(|&p| (-self.f_with_gradient(p).1).normalize_or_zero())
            .collect();
        Ok(mesh)
    }

    fn polygonize_regular(&self, resolution: usize, accuracy: f64) -> Result<Mesh, MeshError> {
        self.polygonize_adaptive(resolution, accuracy)
            .map(|(mesh, _)| mesh)
    }

    /// The regular solid's mesh, sampled only where the surface may be: boxes of cells whose
    /// Bernstein bounds clear zero are skipped, the rest sampled as blocks and marched (see
    /// [`Solid3::polygonize_uniform`] for the mesh it equals), on every thread of the pool with the
    /// `parallel` feature. With how much of the grid it skipped.
    fn polygonize_adaptive(
        &self,
        resolution: usize,
        accuracy: f64,
    ) -> Result<(Mesh, AdaptiveStats), MeshError> {
        let ((mesh, _), stats) = self.adaptive_mesh(resolution, accuracy, Share::WHOLE)?;
        Ok((mesh, stats))
    }

    /// The piece of `share` of the regular solid's mesh.
    fn piece_regular(
        &self,
        resolution: usize,
        accuracy: f64,
        share: Share,
    ) -> Result<Piece, MeshError> {
        let ((mesh, keys), _) = self.adaptive_mesh(resolution, accuracy, share)?;
        Ok(Piece { mesh, keys })
    }

    /// The blocks of `share` of the regular solid's grid, meshed in pieces of consecutive blocks
    /// welded in order ([`make_and_weld`]: on every thread of the pool with the `parallel`
    /// feature).
    fn adaptive_mesh(
        &self,
        resolution: usize,
        accuracy: f64,
        share: Share,
    ) -> Result<(Keyed, AdaptiveStats), MeshError> {
        let grid = self.mesh_grid(resolution)?;
        let roots = SolidRoots::new(self, &grid, accuracy);
        let samples = BlockSamples::new(&roots.xi, &roots.params);
        let (blocks, stats) = adaptive::blocks(roots.xi.points(), roots.xi.degree(), &roots.params);
        let blocks = share.of_blocks(&blocks);
        let marcher = Marcher::new();
        let sample = |block: &Block, out: &mut Vec<f64>| samples.fill(block, out);
        #[cfg(feature = "parallel")]
        let pieces = super::polygonize::pieces_taken_in_turn();
        #[cfg(not(feature = "parallel"))]
        let pieces = 1;
        let parts: Vec<&[Block]> = blocks
            .chunks(blocks.len().div_ceil(pieces).max(1))
            .collect();
        let mesh = make_and_weld(
            parts.len(),
            |k| polygonize_blocks(&grid, parts[k], sample, &mut &roots, &marcher),
            |_| {},
        );
        Ok((mesh, stats))
    }

    /// [`Solid3::polygonize`] of a solid without a space mapping, with what the adaptive meshing
    /// skipped; `None` for one with a space mapping.
    ///
    /// # Errors
    ///
    /// As [`Solid3::polygonize`].
    pub fn polygonize_with_stats(
        &self,
        resolution: usize,
        accuracy: f64,
    ) -> Result<Option<(Mesh, AdaptiveStats)>, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        if self.is_space_mapped() {
            return Ok(None);
        }
        self.polygonize_adaptive(resolution, accuracy).map(Some)
    }

    /// The plain path that [`Solid3::polygonize`] is checked against, for a solid without a space
    /// mapping: every sample of the uniform grid evaluated, every cube marched. The adaptive path
    /// gives the same triangles on the same vertices (in another order); this one costs the cube of
    /// the resolution. A solid with a space mapping is meshed as by [`Solid3::polygonize`].
    ///
    /// # Errors
    ///
    /// As [`Solid3::polygonize`].
    pub fn polygonize_uniform(&self, resolution: usize, accuracy: f64) -> Result<Mesh, MeshError> {
        if !(accuracy.is_finite() && accuracy > 0.0) {
            return Err(MeshError::Accuracy);
        }
        if self.is_space_mapped() {
            return self.polygonize(resolution, accuracy);
        }
        let grid = self.mesh_grid(resolution)?;
        let roots = SolidRoots::new(self, &grid, accuracy);
        let [us, vs, ws] = &roots.params;
        let mut values = roots.xi.eval_grid([us, vs, ws]);
        let mut i = 0;
        for &w in ws {
            for &v in vs {
                let row_inside = inner(v) && inner(w);
                for &u in us {
                    if !(row_inside && inner(u)) {
                        values[i] = clip3(values[i], u, v, w);
                    }
                    i += 1;
                }
            }
        }
        Ok(polygonize(&grid, &values, &mut &roots))
    }
}

/// Strictly inside `(0, 1)`: a parameter where the clipping does not change the sign of `S_ξ`.
fn inner(t: f64) -> bool {
    t > 0.0 && t < 1.0
}

/// The samples of blocks of the grid, each the very value [`Tensor::eval_grid`] gives it (the same
/// basis rows, contracted in the same order: last axis, then the middle, then the first), clipped
/// where a parameter is outside `(0, 1)` as the uniform path clips it. Equal values, equal signs:
/// the blocks mesh as the uniform grid does.
///
/// [`Tensor::eval_grid`]: crate::Tensor::eval_grid
struct BlockSamples<'a> {
    params: &'a [Vec<f64>; 3],
    degree: [usize; 3],
    /// Basis rows at each sample's `u` (transposed: a row per basis function, a value per
    /// sample, so a row of samples is weighed side by side) and at each sample's `v`.
    rows: [Vec<f64>; 2],
    /// The net contracted along `w` at each sample's `w`: `(n + 1)(m + 1)` values each.
    planes: Vec<f64>,
}

impl<'a> BlockSamples<'a> {
    fn new(xi: &Volume<f64>, params: &'a [Vec<f64>; 3]) -> Self {
        let degree = xi.degree();
        let table = |axis: usize| {
            let d = degree[axis] + 1;
            let mut table = vec![0.0; params[axis].len() * d];
            for (row, &t) in table.chunks_exact_mut(d).zip(&params[axis]) {
                basis(degree[axis], t, row);
            }
            table
        };
        let ws = table(2);
        let dl = degree[2] + 1;
        let mut planes = Vec::with_capacity(params[2].len() * xi.points().len() / dl);
        for w in ws.chunks_exact(dl) {
            planes.extend(xi.points().chunks_exact(dl).map(|line| dot(line, w)));
        }
        Self {
            params,
            degree,
            rows: [crate::lanes::transpose(&table(0), degree[0] + 1), table(1)],
            planes,
        }
    }

    fn fill(&self, block: &Block, out: &mut Vec<f64>) {
        // A net of one degree on every axis (the common case) has its own code, with the point
        // counts constants; others take the general one.
        let [dn, dm, dl] = self.degree.map(|d| d + 1);
        if dn == dm && dm == dl {
            match dn {
                2 => return self.fill_in::<2>(block, [2; 2], out),
                3 => return self.fill_in::<3>(block, [3; 2], out),
                4 => return self.fill_in::<4>(block, [4; 2], out),
                5 => return self.fill_in::<5>(block, [5; 2], out),
                6 => return self.fill_in::<6>(block, [6; 2], out),
                _ => {}
            }
        }
        self.fill_in::<{ MAX_DEGREE + 1 }>(block, [dn, dm], out);
    }

    /// [`Self::fill`] for a net of `dn × dm × …` points, at most `L` along `u`.
    #[inline(always)]
    fn fill_in<const L: usize>(&self, block: &Block, [dn, dm]: [usize; 2], out: &mut Vec<f64>) {
        let [us, vs, ws] = self.params;
        let span = |k: usize| block.lo[k]..block.lo[k] + block.size[k] + 1;
        let (a_span, b_span, c_span) = (span(0), span(1), span(2));
        let (a0, na) = (a_span.start, a_span.len());
        let mut line = [0.0; L];
        // The first and last `u` of the block outside `(0, 1)`, where the clipping applies.
        let u_outside = !inner(us[a0]) || !inner(us[a0 + na - 1]);
        for c in c_span {
            let plane = &self.planes[c * dn * dm..(c + 1) * dn * dm];
            let w = ws[c];
            for b in b_span.clone() {
                let v_row = &self.rows[1][b * dm..(b + 1) * dm];
                let v = vs[b];
                for (slot, l) in line.iter_mut().zip(plane.chunks_exact(dm)).take(dn) {
                    *slot = dot(l, v_row);
                }
                let start = out.len();
                crate::lanes::weigh(&line[..dn], &self.rows[0][a0..], us.len(), na, out);
                if u_outside || !(inner(v) && inner(w)) {
                    for (value, &u) in out[start..].iter_mut().zip(&us[a0..]) {
                        if !(inner(u) && inner(v) && inner(w)) {
                            *value = clip3(*value, u, v, w);
                        }
                    }
                }
            }
        }
    }
}

/// `Σ_i p_i b_i`, summed as [`crate::Tensor::eval_grid`] sums (from zero, in order).
#[inline(always)]
fn dot(line: &[f64], b: &[f64]) -> f64 {
    line.iter().zip(b).fold(0.0, |acc, (p, &w)| acc + *p * w)
}

/// Roots on grid edges of a [`Solid3`]: along an edge two parameters are fixed, so `S_ξ` is a Bézier
/// curve whose coefficients are the net contracted with the two fixed basis rows; the gradient across
/// the edge comes from the same contraction with one derivative row.
struct SolidRoots<'a> {
    solid: &'a Solid3,
    xi: Volume<f64>,
    /// Parameters of the samples along each axis, and their basis and derivative rows.
    params: [Vec<f64>; 3],
    basis: [Vec<f64>; 3],
    slope: [Vec<f64>; 3],
    /// The net contracted along w at every sample's `w` (`(n + 1)(m + 1)` values each), and with the
    /// derivative row; and along u at every sample's `u` (`(m + 1)(l + 1)` each).
    w_planes: [Vec<f64>; 2],
    u_planes: [Vec<f64>; 2],
    /// `1 / (max − min)`: from parameter to world derivatives.
    scale: DVec3,
    accuracy: f64,
}

impl<'a> SolidRoots<'a> {
    fn new(solid: &'a Solid3, grid: &SampleGrid, accuracy: f64) -> Self {
        let xi = solid.xi_net();
        let (min, max) = solid.domain();
        let degrees = xi.degree();
        let params: [Vec<f64>; 3] = core::array::from_fn(|axis| {
            (0..grid.dims[axis])
                .map(|a| {
                    (grid.origin[axis] + grid.step[axis] * a as f64 - min[axis])
                        / (max[axis] - min[axis])
                })
                .collect()
        });
        let tables = |axis: usize| {
            let d = degrees[axis] + 1;
            let mut value = vec![0.0; params[axis].len() * d];
            let mut slope = vec![0.0; params[axis].len() * d];
            for (a, &t) in params[axis].iter().enumerate() {
                let (b, db) = basis_and_derivative(degrees[axis], t);
                value[a * d..(a + 1) * d].copy_from_slice(&b[..d]);
                slope[a * d..(a + 1) * d].copy_from_slice(&db[..d]);
            }
            (value, slope)
        };
        let (b0, s0) = tables(0);
        let (b1, s1) = tables(1);
        let (b2, s2) = tables(2);
        let (dn, dm, dl) = (degrees[0] + 1, degrees[1] + 1, degrees[2] + 1);
        let pts = xi.points();
        let mut w_planes = [Vec::new(), Vec::new()];
        for (plane, rows) in w_planes.iter_mut().zip([&b2, &s2]) {
            for row in rows.chunks_exact(dl) {
                for ij in pts.chunks_exact(dl) {
                    plane.push(ij.iter().zip(row).map(|(p, b)| p * b).sum());
                }
            }
        }
        let mut u_planes = [Vec::new(), Vec::new()];
        for (plane, rows) in u_planes.iter_mut().zip([&b0, &s0]) {
            for row in rows.chunks_exact(dn) {
                for jk in 0..dm * dl {
                    plane.push((0..dn).map(|i| pts[i * dm * dl + jk] * row[i]).sum());
                }
            }
        }
        Self {
            solid,
            xi,
            params,
            basis: [b0, b1, b2],
            slope: [s0, s1, s2],
            w_planes,
            u_planes,
            scale: (max - min).recip(),
            accuracy,
        }
    }

    /// Along `axis` through sample `lower`: the coefficients of `S_ξ` as a curve in that parameter, and
    /// of its derivatives along the two other axes (in increasing axis order), from the contracted
    /// planes: `(degree + 1)²` multiply-adds each.
    ///
    /// `pts` are the net's points per axis and `L` at least the most of them: the vertex of a net
    /// of one degree on every axis passes constants, and the sums unroll.
    #[inline(always)]
    fn line<'s, const L: usize>(
        &'s self,
        axis: usize,
        lower: [usize; 3],
        pts: [usize; 3],
    ) -> [[f64; L]; 3] {
        let [dn, dm, dl] = pts;
        let [a, b, c] = lower;
        let row = |table: &'s [Vec<f64>; 3], ax: usize, at: usize, len: usize| -> &'s [f64] {
            &table[ax][at * len..(at + 1) * len]
        };
        let mut out = [[0.0; L]; 3];
        match axis {
            0 | 1 => {
                // The (i, j) plane at this sample's w.
                let size = dn * dm;
                let p = &self.w_planes[0][c * size..(c + 1) * size];
                let dp = &self.w_planes[1][c * size..(c + 1) * size];
                if axis == 0 {
                    let (bv, dbv) = (row(&self.basis, 1, b, dm), row(&self.slope, 1, b, dm));
                    for i in 0..dn {
                        for j in 0..dm {
                            let (x, dx) = (p[i * dm + j], dp[i * dm + j]);
                            out[0][i] += x * bv[j];
                            out[1][i] += x * dbv[j];
                            out[2][i] += dx * bv[j];
                        }
                    }
                } else {
                    let (bu, dbu) = (row(&self.basis, 0, a, dn), row(&self.slope, 0, a, dn));
                    for i in 0..dn {
                        for j in 0..dm {
                            let (x, dx) = (p[i * dm + j], dp[i * dm + j]);
                            out[0][j] += x * bu[i];
                            out[1][j] += x * dbu[i];
                            out[2][j] += dx * bu[i];
                        }
                    }
                }
            }
            _ => {
                // The (j, k) plane at this sample's u.
                let size = dm * dl;
                let q = &self.u_planes[0][a * size..(a + 1) * size];
                let dq = &self.u_planes[1][a * size..(a + 1) * size];
                let (bv, dbv) = (row(&self.basis, 1, b, dm), row(&self.slope, 1, b, dm));
                for j in 0..dm {
                    for k in 0..dl {
                        let (x, dx) = (q[j * dl + k], dq[j * dl + k]);
                        out[0][k] += x * bv[j];
                        out[1][k] += dx * bv[j];
                        out[2][k] += x * dbv[j];
                    }
                }
            }
        }
        out
    }
}

/// A root in `[0, 1]` of the Bézier curve `c[..=degree]` taken along `[t0, t1]`, whose values at
/// the ends are `ends` (the samples there) of opposite signs: Newton's method from the linear
/// estimate, kept in the bracket (a step that leaves it bisects), until `|value| ≤ accuracy`.
/// Along one grid edge the curve is nearly a line, so two or three steps do. The root's `t` with
/// the curve's value and slope there (of the last step); `None` where the ends do not bracket a
/// root or the steps run out.
#[inline(always)]
fn newton_on_edge<const L: usize>(
    c: &[f64; L],
    degree: usize,
    t0: f64,
    t1: f64,
    (p0, p1): (f64, f64),
    accuracy: f64,
) -> Option<(f64, (f64, f64))> {
    let at = |t: f64| bezier1_with_slope(c, degree, t0 + (t1 - t0) * t);
    if (p0 > 0.0) == (p1 > 0.0) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut t = linear_root(p0, p1);
    for _ in 0..crate::math::ROOT_STEPS {
        let (v, slope) = at(t);
        if v.abs() <= accuracy {
            return Some((t, (v, slope)));
        }
        if (v > 0.0) == (p0 > 0.0) {
            lo = t;
        } else {
            hi = t;
        }
        let next = t - v / (slope * (t1 - t0));
        t = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= 1e-15 {
            break;
        }
    }
    None
}

/// A Bézier curve with coefficients `c[..=degree]` at `t` and its derivative there, by de
/// Casteljau (the derivative is `degree` times the difference of the last level's two points).
#[inline(always)]
fn bezier1_with_slope<const L: usize>(c: &[f64; L], degree: usize, t: f64) -> (f64, f64) {
    let mut p = *c;
    for k in 1..degree {
        casteljau_level(&mut p, t, degree - k);
    }
    let slope = degree as f64 * (p[1] - p[0]);
    (p[0] + (p[1] - p[0]) * t, slope)
}

/// A Bézier curve with coefficients `c[..=degree]` at `t`, by de Casteljau.
#[inline(always)]
fn bezier1<const L: usize>(c: &[f64; L], degree: usize, t: f64) -> f64 {
    let mut p = *c;
    for k in 1..=degree {
        casteljau_level(&mut p, t, degree - k);
    }
    p[0]
}

/// Two Bézier curves of one degree at `t`, by de Casteljau in one pass: the same values as two
/// calls of [`bezier1`].
#[inline(always)]
fn bezier1_pair<const L: usize>(a: &[f64; L], b: &[f64; L], degree: usize, t: f64) -> [f64; 2] {
    let mut p: [[f64; 2]; L] = core::array::from_fn(|i| [a[i], b[i]]);
    for k in 1..=degree {
        // As `casteljau_level`, two curves side by side.
        let end = if L <= crate::bernstein::STEP_WHOLE {
            L - 1
        } else {
            degree - k + 1
        };
        for i in 0..end {
            let next = p[i + 1];
            for (v, n) in p[i].iter_mut().zip(next) {
                *v += (n - *v) * t;
            }
        }
    }
    p[0]
}

/// The blocks of a Bézier solid all sample the one polynomial: nothing to agree on.
impl BlockRoots for &SolidRoots<'_> {}

impl EdgeRoots for &SolidRoots<'_> {
    fn vertex(&mut self, axis: usize, lower: [usize; 3], f0: f64, f1: f64) -> (f64, DVec3) {
        // A net of one degree on every axis (the common case) has its own code, with the point
        // count a constant; others take the general one.
        let [n, m, l] = self.xi.degree();
        if n == m && m == l {
            match n {
                1 => return self.vertex_in::<2>(axis, lower, (f0, f1), [2; 3]),
                2 => return self.vertex_in::<3>(axis, lower, (f0, f1), [3; 3]),
                3 => return self.vertex_in::<4>(axis, lower, (f0, f1), [4; 3]),
                4 => return self.vertex_in::<5>(axis, lower, (f0, f1), [5; 3]),
                5 => return self.vertex_in::<6>(axis, lower, (f0, f1), [6; 3]),
                _ => {}
            }
        }
        self.vertex_in::<{ MAX_DEGREE + 1 }>(axis, lower, (f0, f1), [n + 1, m + 1, l + 1])
    }

    fn centre(&mut self, mean: DVec3, lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
        self.centre_of(mean, lo, hi)
    }
}

impl SolidRoots<'_> {
    /// [`EdgeRoots::vertex`] for a net of `pts` points per axis, at most `L` on any.
    #[inline(always)]
    fn vertex_in<const L: usize>(
        &self,
        axis: usize,
        lower: [usize; 3],
        (f0, f1): (f64, f64),
        pts: [usize; 3],
    ) -> (f64, DVec3) {
        let [coef, dp, dq] = self.line::<L>(axis, lower, pts);
        // Of one degree on every axis, the degree is `pts[0] − 1`, a constant where the caller
        // passed constants (`pts[axis]` with `axis` unknown is a load, and the loops would not
        // unroll).
        let degree = if pts[1] == pts[0] && pts[2] == pts[0] {
            pts[0] - 1
        } else {
            pts[axis] - 1
        };
        let (t0, t1) = (
            self.params[axis][lower[axis]],
            self.params[axis][lower[axis] + 1],
        );
        let uvw: [f64; 3] = core::array::from_fn(|ax| self.params[ax][lower[ax]]);
        let g = |t: f64| {
            let s = t0 + (t1 - t0) * t;
            let mut at = uvw;
            at[axis] = s;
            clip3(bezier1(&coef, degree, s), at[0], at[1], at[2])
        };
        // The end values of f itself (the samples may hold S_ξ, of the same sign): refine only if
        // they still bracket a root after rounding, else keep the linear estimate.
        // Inside the box F_s > 0, where f = S_ξ & F_s has the zeros of S_ξ and |f| ≤ |S_ξ| + S_ξ²/(2F_s):
        // refine on the polynomial alone (no square roots), then check f; otherwise refine on f.
        let inner = |t: f64| t > 0.0 && t < 1.0;
        let interior = uvw
            .iter()
            .enumerate()
            .all(|(ax, &t)| ax == axis || inner(t))
            && inner(t0)
            && inner(t1);
        // Where every strip `t(1 − t)` along the edge is at least the accuracy, `F_s` (their
        // R-conjunction, at least 0.34 of the least of them) is above a quarter of it, and then
        // `|S_ξ| ≤ accuracy / 2` gives `|f| ≤ |S_ξ| + S_ξ²/(2F_s) ≤ accuracy`: no need to check f.
        let strip = |t: f64| t * (1.0 - t);
        let far_from_faces = uvw
            .iter()
            .enumerate()
            .all(|(ax, &t)| ax == axis || strip(t) >= self.accuracy)
            && strip(t0).min(strip(t1)) >= self.accuracy;
        let quick = if interior {
            newton_on_edge(&coef, degree, t0, t1, (f0, f1), 0.5 * self.accuracy)
                .filter(|&(t, _)| far_from_faces || g(t).abs() <= self.accuracy)
        } else {
            None
        };
        // The root, and S_ξ with its slope there (Newton's last step has them).
        let (t, (value, slope)) = match quick {
            Some(found) => found,
            None => {
                let (g0, g1) = (g(0.0), g(1.0));
                let t = if (g0 > 0.0) != (g1 > 0.0) {
                    illinois(g, g0, g1, self.accuracy)
                } else {
                    linear_root(f0, f1)
                };
                (t, bezier1_with_slope(&coef, degree, t0 + (t1 - t0) * t))
            }
        };
        let s = t0 + (t1 - t0) * t;
        let mut at = uvw;
        at[axis] = s;
        let mut grad = [0.0; 3];
        grad[axis] = slope;
        let (p, q) = other_axes(axis);
        [grad[p], grad[q]] = bezier1_pair(&dp, &dq, degree, s);
        // f = S_ξ & F_s has the gradient f_S·∇S_ξ + f_F·∇F_s, where f_S = 1 − S/h ≥ ½ and
        // f_F = 1 − F/h ≤ S²/(2F²) (h = √(S² + F²), F > 0, |S| ≤ F/2). With F ≥ 0.34·m (m the
        // least strip) and |∇F_s| < 7 (each partial of `&` at most 2, each strip's slope at most
        // 1), the second term turns the normal by less than 61·σ·S²/(m²·|∇S_ξ ⊙ scale|), σ the
        // largest scale. Where that is below 1e-17 the normal of ∇S_ξ is the normal of ∇f to
        // rounding, and the clipping's square roots and divisions are skipped (a root of Newton's
        // method usually has S within a few ulps of zero).
        let world = DVec3::from_array(grad) * self.scale;
        let m = at
            .iter()
            .map(|&x| x * (1.0 - x))
            .fold(f64::INFINITY, f64::min);
        let turn = 61.0 * self.scale.max_element() * value * value;
        let g = if m > 0.0
            && 4.0 * value.abs() <= m
            && turn * turn <= 1e-34 * (m * m) * (m * m) * world.length_squared()
        {
            world
        } else {
            DVec3::from_array(clip_with_gradient(value, grad, at).1) * self.scale
        };
        (t, -g.normalize_or_zero())
    }

    /// [`EdgeRoots::centre`].
    fn centre_of(&self, mean: DVec3, lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
        // Newton steps along the gradient, kept in the cube.
        let mut p = mean;
        let mut grad = DVec3::ZERO;
        for _ in 0..8 {
            let (f, g) = self.solid.f_with_gradient(p);
            grad = g;
            let g2 = g.length_squared();
            if f.abs() <= self.accuracy || g2 == 0.0 || !g2.is_finite() {
                break;
            }
            p = (p - g * (f / g2)).clamp(lo, hi);
        }
        (p, -grad.normalize_or_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A ball of radius `r` (in parameter units) about the middle of the box `[min, max]`: in degree 2
    /// the Bernstein coefficients of `(t − ½)²` are `(¼, −¼, ¼)`, so `S_ξ = r² − |t − ½|²` exactly.
    fn ball(r: f64, min: DVec3, max: DVec3) -> Solid3 {
        let c = [0.25, -0.25, 0.25];
        Solid3::regular([2, 2, 2], min, max, |[i, j, k]| r * r - c[i] - c[j] - c[k]).unwrap()
    }

    #[test]
    fn a_net_whose_points_share_one_x_meshes_closed() {
        // The box is 2.2e-308 wide beside x = 7.8e-12: below rounding.
        let volume = Volume::from_fn([1, 1, 1], |[i, j, k]| {
            DVec4::new(7.8e-12 + 2.2e-308 * i as f64, j as f64, k as f64, 1.0)
        })
        .unwrap();
        let solid = Solid3::try_from_net(volume).unwrap();
        for res in [1, 2, 6, 12] {
            let mesh = solid.polygonize(res, 1e-9).unwrap();
            assert!(mesh.check_closed_manifold().is_ok(), "{res}");
            assert!(mesh.positions.iter().all(|p| p.is_finite()));
        }
    }

    #[test]
    fn ball_mesh_is_closed_accurate_and_its_volume_converges() {
        let (min, max) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(1.0, 2.0, 4.0));
        let r = 0.4;
        let solid = ball(r, min, max);
        // The box is a 2-cube: the ball's radius in space is 2r.
        let exact = 4.0 / 3.0 * core::f64::consts::PI * (2.0 * r).powi(3);
        let centre = (min + max) / 2.0;
        let mut last_error = f64::INFINITY;
        for res in [8, 16, 32, 64] {
            let accuracy = 1e-10;
            let mesh = solid.polygonize(res, accuracy).unwrap();
            mesh.check_closed_manifold().unwrap();
            assert_eq!(mesh.euler_characteristic(), 2);
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                assert!(solid.f(*p).abs() <= accuracy, "f = {} at {p}", solid.f(*p));
                assert!((n.length() - 1.0).abs() < 1e-12);
                // On a ball the outward normal is the radial direction.
                assert!(n.dot((*p - centre).normalize()) > 1.0 - 1e-9);
            }
            let error = (mesh.volume() - exact).abs() / exact;
            assert!(
                error < 0.6 * last_error,
                "res {res}: error {error} after {last_error}"
            );
            last_error = error;
        }
        assert!(last_error < 2e-3, "{last_error}");
    }

    #[test]
    fn a_solid_cut_by_the_box_is_closed_by_the_box_faces() {
        // ξ = 0.5 everywhere: the whole box is inside; the mesh is the box itself, vertices on its faces.
        let solid = Solid3::regular(
            [1, 2, 1],
            DVec3::ZERO,
            DVec3::new(2.0, 1.0, 1.0),
            |[_, _, _]| 0.5,
        )
        .unwrap();
        let mesh = solid.polygonize(10, 1e-12).unwrap();
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), 2);
        // Marching cubes bevels the box's edges: a prism of section (h/2)²/2 along each of them.
        let h = 0.2;
        let bevel = 16.0 * (h / 2.0) * (h / 2.0) / 2.0;
        // (The corners, where three bevels meet, give a little back.)
        assert!(
            (mesh.volume() - (2.0 - bevel)).abs() < 0.01,
            "{}",
            mesh.volume()
        );
        for p in &mesh.positions {
            let on_face = p.x.abs() < 1e-9
                || (p.x - 2.0).abs() < 1e-9
                || p.y.abs() < 1e-9
                || (p.y - 1.0).abs() < 1e-9
                || p.z.abs() < 1e-9
                || (p.z - 1.0).abs() < 1e-9;
            assert!(on_face, "{p}");
        }
    }

    #[test]
    fn bad_arguments_are_typed_errors() {
        let solid = ball(0.3, DVec3::ZERO, DVec3::ONE);
        assert_eq!(
            solid.polygonize(0, 1e-6),
            Err(MeshError::Resolution { got: 0 })
        );
        assert_eq!(
            solid.polygonize(MAX_RESOLUTION + 1, 1e-6),
            Err(MeshError::Resolution {
                got: MAX_RESOLUTION + 1
            })
        );
        for accuracy in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(solid.polygonize(8, accuracy), Err(MeshError::Accuracy));
        }
        // An empty solid is an empty mesh, not an error.
        let empty = Solid3::regular([1, 1, 1], DVec3::ZERO, DVec3::ONE, |[_, _, _]| -1.0).unwrap();
        assert_eq!(empty.polygonize(8, 1e-6).unwrap().triangle_count(), 0);
    }

    #[test]
    fn cells_are_near_cubes_in_a_long_box() {
        let solid = ball(0.3, DVec3::ZERO, DVec3::new(4.0, 1.0, 0.5));
        let grid = solid.mesh_grid(40).unwrap();
        assert_eq!(grid.dims, [42, 12, 7]);
        assert!((grid.step.x - 0.1).abs() < 1e-12 && grid.step.max_element() <= 0.1 + 1e-12);
    }

    /// A ball in a warped net: the forward path's vertices lie on `f = 0` as the inverse map sees it,
    /// its normals are the inverse map's `−∇f`, and the sampled path (the oracle for folds) encloses
    /// the same volume.
    #[test]
    fn warped_volume_forward_mesh_lies_on_the_inverse_zero_set() {
        let mut rng = crate::testutil::Rng::new(81);
        let base = ball(0.4, DVec3::ZERO, DVec3::ONE);
        let volume = Volume::from_fn([2, 2, 2], |[i, j, k]| {
            let p = base.net()[[i, j, k]];
            let d = DVec3::new(
                rng.range(-0.08, 0.08),
                rng.range(-0.08, 0.08),
                rng.range(-0.08, 0.08),
            );
            (p.truncate() + d).extend(p.w)
        })
        .unwrap();
        let solid = Solid3::try_from_net(volume).unwrap();
        assert!(solid.inverse().unwrap().injective());
        let mesh = solid.polygonize(24, 1e-12).unwrap();
        mesh.check_closed_manifold().unwrap();
        assert_eq!(mesh.euler_characteristic(), 2);
        assert!(mesh.volume() > 0.0, "outward");
        for (&p, &n) in mesh.positions.iter().zip(&mesh.normals) {
            let v = solid.evaluate(p, crate::inverse::Method::Clipping);
            assert_eq!(v.preimages, 1);
            assert!(v.f.abs() < 1e-10, "f = {} at {p}", v.f);
            let (_, g) = solid.f_with_gradient(p);
            assert!((n + g.normalize()).length() < 1e-8, "{n} vs {g}");
        }
        let mut steps = Vec::new();
        let sampled = solid
            .polygonize_sampled(24, &mut |done, total| steps.push((done, total)))
            .unwrap();
        sampled.check_closed_manifold().unwrap();
        // Each layer of samples along z reported, in order, the mesh's step left for the end.
        let layers = solid.mesh_grid(24).unwrap().dims[2];
        assert_eq!(
            steps,
            (1..layers).map(|d| (d, layers + 1)).collect::<Vec<_>>()
        );
        let (a, b) = (mesh.volume(), sampled.volume());
        assert!((a - b).abs() < 0.03 * a, "{a} vs {b}");
    }

    /// A net turned inside out (x reversed) keeps the mesh outward.
    #[test]
    fn an_inside_out_net_still_meshes_outward() {
        let base = ball(0.4, DVec3::ZERO, DVec3::ONE);
        let volume = Volume::from_fn([2, 2, 2], |[i, j, k]| {
            let p = base.net()[[i, j, k]];
            DVec4::new(1.0 - p.x, p.y, p.z, p.w)
        })
        .unwrap();
        let solid = Solid3::try_from_net(volume).unwrap();
        assert!(solid.inverse().unwrap().injective());
        let mesh = solid.polygonize(16, 1e-12).unwrap();
        mesh.check_closed_manifold().unwrap();
        let want = base.polygonize(16, 1e-12).unwrap().volume();
        assert!(
            (mesh.volume() - want).abs() < 1e-9,
            "{} vs {want}",
            mesh.volume()
        );
    }

    /// The sheet mesh is the mesh where the map is regular or injective, and on a folded net it is
    /// a closed mesh of the parameter-space solid mapped forward (every vertex an image `S(u)`).
    #[test]
    fn sheets_are_the_mesh_when_injective_and_the_forward_image_when_folded() {
        let base = ball(0.4, DVec3::ZERO, DVec3::ONE);
        assert_eq!(
            base.polygonize_sheets(12, 1e-9).unwrap(),
            base.polygonize(12, 1e-9).unwrap()
        );
        let moved = Volume::from_fn([2, 2, 2], |[i, j, k]| {
            let p = base.net()[[i, j, k]];
            DVec4::new(p.x + 0.1 * p.y * p.y, p.y, p.z, p.w)
        })
        .unwrap();
        let moved = Solid3::try_from_net(moved).unwrap();
        assert!(moved.inverse().unwrap().injective());
        assert_eq!(
            moved.polygonize_sheets(12, 1e-9).unwrap(),
            moved.polygonize(12, 1e-9).unwrap()
        );
        let mut rng = crate::testutil::Rng::new(82);
        let folded = crate::inverse::tests::warped_volume(&mut rng, [2, 2, 2], 0.45);
        let folded = Solid3::try_from_net(folded).unwrap();
        let mesh = folded.polygonize_sheets(12, 1e-9).unwrap();
        mesh.check_closed_manifold().unwrap();
        let (lo, hi) = folded.net().bounds();
        for p in &mesh.positions {
            assert!(p.cmpge(lo.truncate() - DVec3::splat(1e-9)).all());
            assert!(p.cmple(hi.truncate() + DVec3::splat(1e-9)).all());
        }
        assert!(matches!(
            folded.polygonize_sheets(12, f64::NAN),
            Err(MeshError::Accuracy)
        ));
    }

    /// A folded net has no certificate: the sampled path gives a closed mesh of the union.
    #[test]
    fn a_folded_net_meshes_by_sampling() {
        let mut rng = crate::testutil::Rng::new(82);
        let volume = crate::inverse::tests::warped_volume(&mut rng, [2, 2, 2], 0.45);
        let solid = Solid3::try_from_net(volume).unwrap();
        let mesh = solid.polygonize(12, 1e-9).unwrap();
        mesh.check_closed_manifold().unwrap();
    }

    /// `a` and `b` are the same mesh up to the order of vertices and triangles: the same vertices
    /// within `tol` (positions and normals) and the same triangles on them, the same way round.
    fn assert_same_mesh(a: &Mesh, b: &Mesh, tol: f64) {
        assert_eq!(a.positions.len(), b.positions.len(), "vertex counts");
        assert_eq!(a.triangles.len(), b.triangles.len(), "triangle counts");
        let order = |m: &Mesh| {
            let mut o: Vec<usize> = (0..m.positions.len()).collect();
            o.sort_by(|&i, &j| {
                let (p, q) = (m.positions[i].to_array(), m.positions[j].to_array());
                p.partial_cmp(&q).unwrap_or(core::cmp::Ordering::Equal)
            });
            o
        };
        let (oa, ob) = (order(a), order(b));
        let mut to_b = vec![0u32; a.positions.len()];
        for (&i, &j) in oa.iter().zip(&ob) {
            assert!(a.positions[i].distance(b.positions[j]) <= tol, "vertex {i}");
            assert!(a.normals[i].distance(b.normals[j]) <= tol, "normal {i}");
            to_b[i] = j as u32;
        }
        let canonical = |t: [u32; 3]| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        };
        let mut ta: Vec<[u32; 3]> = a
            .triangles
            .iter()
            .map(|t| canonical(t.map(|v| to_b[v as usize])))
            .collect();
        let mut tb: Vec<[u32; 3]> = b.triangles.iter().map(|&t| canonical(t)).collect();
        ta.sort_unstable();
        tb.sort_unstable();
        assert!(ta == tb, "the triangles differ");
    }

    use crate::Axis;

    /// A degree-`d` ball in `[min, max]` with pseudo-random ripples on its control values.
    fn rippled(d: usize, ripple: f64, seed: u64, min: DVec3, max: DVec3) -> Solid3 {
        let mut xi = ball(0.4, min, max).xi_net();
        for axis in [Axis::U, Axis::V, Axis::W] {
            for _ in 2..d {
                xi = xi.elevate(axis).unwrap();
            }
        }
        let mut rng = crate::testutil::Rng::new(seed);
        let [n, m, l] = xi.degree();
        let pts = xi.points().to_vec();
        Solid3::regular([n, m, l], min, max, |[i, j, k]| {
            pts[(i * (m + 1) + j) * (l + 1) + k] + rng.range(-ripple, ripple)
        })
        .unwrap()
    }

    #[test]
    fn adaptive_meshes_equal_the_uniform_grid_on_the_same_cells() {
        let solids = [
            ball(0.3, DVec3::ZERO, DVec3::ONE),
            // Past the box: the surface meets the box's faces, where the clipping makes it.
            ball(0.6, DVec3::new(-1.0, 0.0, 2.0), DVec3::new(1.0, 0.5, 3.0)),
            rippled(4, 0.05, 1, DVec3::ZERO, DVec3::ONE),
            rippled(
                3,
                0.2,
                2,
                DVec3::new(-2.0, -1.0, 0.0),
                DVec3::new(2.0, 1.0, 0.5),
            ),
            rippled(6, 0.1, 3, DVec3::ZERO, DVec3::splat(10.0)),
        ];
        for (s, solid) in solids.iter().enumerate() {
            for res in [1, 5, 16, 33, 70] {
                let uniform = solid.polygonize_uniform(res, 1e-9).unwrap();
                let (adaptive, stats) = solid.polygonize_with_stats(res, 1e-9).unwrap().unwrap();
                assert_same_mesh(&adaptive, &uniform, 1e-9);
                adaptive.check_closed_manifold().unwrap();
                // A solid inside its box skips most of the grid; one that fills it, some.
                if res == 70 {
                    let share = if s == 1 || s == 3 { 5 } else { 2 };
                    assert!(stats.skipped * share > stats.cells, "solid {s}: {stats:?}");
                }
            }
        }
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn threads_make_the_mesh_one_thread_makes() {
        let solid = rippled(4, 0.05, 5, DVec3::ZERO, DVec3::ONE);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| solid.polygonize(60, 1e-9).unwrap())
        };
        let one = on(1);
        assert!(one.triangle_count() > 1000);
        for threads in [2, 3, 8] {
            assert_eq!(on(threads), one, "{threads} threads");
        }
    }

    /// The code for a net of one degree on every axis (its point counts constants) computes what
    /// the general code does, bit for bit: the samples of every block, and the root and normal on
    /// every edge the surface crosses.
    #[test]
    fn the_code_for_one_degree_is_the_general_code() {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for degree in 2..=6 {
            let solid = rippled(degree, 0.05, degree as u64, DVec3::ZERO, DVec3::ONE);
            let grid = solid.mesh_grid(20).unwrap();
            let roots = SolidRoots::new(&solid, &grid, 1e-9);
            let pts = [degree + 1; 3];
            let samples = BlockSamples::new(&roots.xi, &roots.params);
            let (blocks, _) = adaptive::blocks(roots.xi.points(), roots.xi.degree(), &roots.params);
            assert!(!blocks.is_empty());
            for block in &blocks {
                let (mut fixed, mut general) = (Vec::new(), Vec::new());
                samples.fill(block, &mut fixed);
                samples.fill_in::<{ MAX_DEGREE + 1 }>(block, [pts[0], pts[1]], &mut general);
                assert_eq!(bits(&fixed), bits(&general), "degree {degree}, {block:?}");
            }
            let [us, vs, ws] = &roots.params;
            let values = roots.xi.eval_grid([us, vs, ws]);
            let dims = [us.len(), vs.len(), ws.len()];
            let at = |p: [usize; 3]| values[(p[2] * dims[1] + p[1]) * dims[0] + p[0]];
            let mut crossings = 0;
            for axis in 0..3 {
                for c in 0..dims[2] {
                    for b in 0..dims[1] {
                        for a in 0..dims[0] {
                            let lower = [a, b, c];
                            let mut upper = lower;
                            upper[axis] += 1;
                            if upper[axis] == dims[axis] {
                                continue;
                            }
                            let (f0, f1) = (at(lower), at(upper));
                            if (f0 > 0.0) == (f1 > 0.0) {
                                continue;
                            }
                            crossings += 1;
                            let (t, n) = (&roots).vertex(axis, lower, f0, f1);
                            let (t2, n2) =
                                roots.vertex_in::<{ MAX_DEGREE + 1 }>(axis, lower, (f0, f1), pts);
                            assert_eq!(t.to_bits(), t2.to_bits(), "degree {degree}");
                            assert_eq!(bits(&n.to_array()), bits(&n2.to_array()));
                            // The normal is that of the clipped f's gradient (the clipping's
                            // term is dropped only where it cannot turn it).
                            let mut p = grid.point(a, b, c);
                            p[axis] += t * grid.step[axis];
                            let (_, g) = solid.f_with_gradient(p);
                            let exact = -g.normalize();
                            assert!(
                                (n - exact).length() < 1e-9,
                                "degree {degree}: {n} against {exact}"
                            );
                        }
                    }
                }
            }
            assert!(crossings > 100, "degree {degree}: {crossings} crossings");
        }
    }

    /// On a pool of several threads the pieces are made and welded as they come, in whatever
    /// order the threads finish them: the mesh is the one thread's, bit for bit.
    #[cfg(feature = "parallel")]
    #[test]
    fn the_mesh_made_on_many_threads_is_the_mesh_of_one() {
        let solid = rippled(4, 0.05, 4, DVec3::ZERO, DVec3::ONE);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| solid.polygonize(48, 1e-9).unwrap())
        };
        let one = on(1);
        assert!(one.triangle_count() > 1000);
        for threads in [2, 3, 5] {
            for _ in 0..3 {
                assert_eq!(on(threads), one, "{threads} threads");
            }
        }
    }

    #[test]
    fn pieces_welded_in_order_are_the_mesh_of_one_walk() {
        let solid = rippled(4, 0.05, 4, DVec3::ZERO, DVec3::ONE);
        let grid = solid.mesh_grid(40).unwrap();
        let roots = SolidRoots::new(&solid, &grid, 1e-9);
        let samples = BlockSamples::new(&roots.xi, &roots.params);
        let (blocks, _) = adaptive::blocks(roots.xi.points(), roots.xi.degree(), &roots.params);
        assert!(blocks.len() > 10);
        let marcher = Marcher::new();
        let sample = |block: &Block, out: &mut Vec<f64>| samples.fill(block, out);
        let whole = polygonize_blocks(&grid, &blocks, sample, &mut &roots, &marcher).0;
        for chunk in [1, 3, 17] {
            let pieces = blocks
                .chunks(chunk)
                .map(|part| polygonize_blocks(&grid, part, sample, &mut &roots, &marcher))
                .collect();
            let welded = super::super::polygonize::weld(pieces);
            assert_eq!(welded, whole, "chunks of {chunk}");
        }
    }

    /// A mesh as a triangle list (each triangle's three positions and normals): what a page draws.
    fn soup(mesh: &Mesh) -> Vec<[DVec3; 6]> {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| v as usize);
                let (p, n) = (&mesh.positions, &mesh.normals);
                [p[a], p[b], p[c], n[a], n[b], n[c]]
            })
            .collect()
    }

    /// A mesh made in shares: the pieces welded in order are the mesh made whole, and the pieces'
    /// triangles one after another are its triangles on the same vertices, bit for bit (a vertex
    /// two shares have is computed from the same samples by both). For a regular solid, an
    /// injective map (made in parameter space and mapped forward), and a folded net (sheets, and the
    /// sampled path that the first share makes whole).
    #[test]
    fn shares_weld_into_the_whole_mesh_and_list_its_triangles() {
        let base = ball(0.4, DVec3::ZERO, DVec3::ONE);
        let moved = Volume::from_fn([2, 2, 2], |[i, j, k]| {
            let p = base.net()[[i, j, k]];
            DVec4::new(p.x + 0.1 * p.y * p.y, p.y, p.z, p.w)
        })
        .unwrap();
        let moved = Solid3::try_from_net(moved).unwrap();
        let mut rng = crate::testutil::Rng::new(82);
        let folded = crate::inverse::tests::warped_volume(&mut rng, [2, 2, 2], 0.45);
        let folded = Solid3::try_from_net(folded).unwrap();
        let solids = [
            ("rippled", rippled(4, 0.05, 4, DVec3::ZERO, DVec3::ONE), 40),
            ("injective", moved, 20),
            ("folded", folded, 10),
        ];
        for (name, solid, res) in &solids {
            let whole = solid.polygonize(*res, 1e-9).unwrap();
            let sheets = solid.polygonize_sheets(*res, 1e-9).unwrap();
            assert!(whole.triangle_count() > 100, "{name}");
            for count in [1, 2, 3, 7] {
                let shares = (0..count).map(|k| Share::new(k, count).unwrap());
                let pieces: Vec<Piece> = shares
                    .clone()
                    .map(|s| solid.polygonize_share(*res, 1e-9, s).unwrap())
                    .collect();
                let listed: Vec<_> = pieces.iter().flat_map(|p| soup(&p.mesh)).collect();
                assert_eq!(listed, soup(&whole), "{name}, {count} shares: triangles");
                assert_eq!(Piece::weld(pieces), whole, "{name}, {count} shares: welded");
                let pieces: Vec<Piece> = shares
                    .map(|s| solid.polygonize_sheets_share(*res, 1e-9, s).unwrap())
                    .collect();
                let listed: Vec<_> = pieces.iter().flat_map(|p| soup(&p.mesh)).collect();
                assert_eq!(listed, soup(&sheets), "{name}, {count} sheet shares");
                assert_eq!(Piece::weld(pieces), sheets, "{name}, {count} sheet shares");
            }
        }
        let one = Share::new(0, 2).unwrap();
        assert!(matches!(
            base.polygonize_share(0, 1e-9, one),
            Err(MeshError::Resolution { got: 0 })
        ));
        assert!(matches!(
            base.polygonize_share(8, f64::NAN, one),
            Err(MeshError::Accuracy)
        ));
    }
}
