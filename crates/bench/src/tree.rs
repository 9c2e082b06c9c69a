//! A model of many solids: 20 leaves (eight 4×4×4 Bézier volumes, six spheres, four boxes, two
//! tori) in ten blended pairs under one union. Grid evaluation of the whole tree (every sample),
//! and meshing, which bounds boxes of cells by interval arithmetic and samples only where the
//! surface may be; the share of cells skipped is in the note.

use bezsolid_core::Solid3;
use bezsolid_core::mesh::Share;
use bezsolid_core::model::{CoordAxis, ModelFile, SolidSpec as S};
use bezsolid_core::tree::{MeshCache, ModelTree, Tree};
use glam::DVec3;

use crate::{Clock, Row, time};

/// The benchmark's tree (its model file).
#[must_use]
pub fn bench_tree() -> ModelFile {
    bench_tree_with(0.0)
}

/// The benchmark's tree with one inner control value of its third volume raised by `bump`: an
/// edit of one solid.
#[must_use]
pub fn bench_tree_with(bump: f64) -> ModelFile {
    // Pair k sits at (x, y) on a 5 × 2 grid, 1.6 apart.
    let at = |k: usize| DVec3::new((k % 5) as f64 * 1.6, (k / 5) as f64 * 1.6, 0.0);
    let volume = |n: usize| {
        let lo = at(n) - DVec3::splat(0.6);
        let v = Solid3::regular([3, 3, 3], lo, lo + DVec3::splat(1.2), |[i, j, k]| {
            // A ball of degree 3, rippled so that no net is like another.
            let d = |a: usize| (a as f64 - 1.5).abs();
            let raised = if n == 2 && [i, j, k] == [1, 2, 1] {
                bump
            } else {
                0.0
            };
            0.35 - 0.18 * (d(i) + d(j) + d(k))
                + 0.02 * ((i * 3 + j * 5 + k * 7 + k) % 4) as f64
                + raised
        })
        .unwrap_or_else(|_| unreachable!("a valid net"));
        ModelFile::from_solid3(&v).solid
    };
    let sphere = |k: usize| S::Sphere {
        center: (at(k) + DVec3::new(0.45, 0.3, 0.35)).to_array(),
        radius: 0.4,
    };
    let cube = |k: usize, h: f64| {
        let c = at(k) + DVec3::new(-0.3, 0.35, -0.2);
        S::Box {
            min: (c - DVec3::splat(h)).to_array(),
            max: (c + DVec3::new(h, h * 1.5, h)).to_array(),
        }
    };
    let torus = |k: usize, axis| S::Torus {
        center: at(k).to_array(),
        axis,
        major: 0.5,
        minor: 0.15,
    };
    let blend = |a: S, b: S| S::BlendUnion {
        of: vec![a, b],
        a0: 0.05,
        a1: 0.5,
        a2: 0.5,
    };
    let mut pairs = Vec::new();
    for k in 0..6 {
        pairs.push(blend(volume(k), sphere(k)));
    }
    pairs.push(blend(volume(6), cube(6, 0.35)));
    pairs.push(blend(volume(7), cube(7, 0.3)));
    pairs.push(blend(cube(8, 0.4), torus(8, CoordAxis::Z)));
    pairs.push(blend(cube(9, 0.35), torus(9, CoordAxis::X)));
    ModelFile::from_spec(S::Union { of: pairs })
}

/// The benchmark's tree, compiled.
#[must_use]
pub fn tree() -> Tree<3> {
    tree_with(0.0)
}

/// [`bench_tree_with`], compiled.
#[must_use]
pub fn tree_with(bump: f64) -> Tree<3> {
    match bench_tree_with(bump).to_tree() {
        Ok(ModelTree::Space(t)) => t,
        _ => unreachable!("a valid 3D tree"),
    }
}

/// Grid evaluation of every sample, and meshing with cells skipped, at 128 and 256 cells along
/// the longest side (64 when `quick`).
pub fn suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let tree = tree();
    let (lo, hi) = tree
        .bounds()
        .unwrap_or_else(|| unreachable!("a bounded tree"));
    let sizes: &[usize] = if quick { &[64] } else { &[128, 256] };
    let mut rows = Vec::new();
    for &n in sizes {
        // The samples meshing takes, every one evaluated, as a grid (the Bézier leaves axis at a
        // time).
        let longest = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
        let step = longest / n as f64;
        let axis = |i: usize| -> Vec<f64> {
            let count = ((hi[i] - lo[i]) / step).ceil() as usize + 2;
            (0..count)
                .map(|a| lo[i] - step / 2.0 + a as f64 * step)
                .collect()
        };
        let (xs, ys, zs) = (axis(0), axis(1), axis(2));
        let points = (xs.len() * ys.len() * zs.len()) as f64;
        let (ms, runs, sum) = time(clock, budget, || {
            tree.f_grid([&xs, &ys, &zs]).iter().sum::<f64>()
        });
        rows.push(Row {
            case: "tree of 20 solids: grid evaluation, every sample".into(),
            who: "bezsolid".into(),
            n,
            ms,
            runs,
            extra: points / (ms / 1000.0),
            note: format!("at {n}: {points} samples (checksum {sum:.3e})"),
        });
        let (ms, runs, (triangles, stats)) = time(clock, budget, || {
            let (mesh, stats) = tree
                .polygonize_with_stats(n, 1e-9, None)
                .unwrap_or_else(|_| unreachable!("valid arguments"));
            (mesh.triangle_count(), stats)
        });
        rows.push(Row {
            case: "tree of 20 solids: polygonize".into(),
            who: "bezsolid (interval bounds skip cells; vertices on f = 0 within 1e-9)".into(),
            n,
            ms,
            runs,
            extra: triangles as f64,
            note: format!(
                "{:.1} % of {} cells skipped by the bounds, {} samples evaluated",
                100.0 * stats.skipped as f64 / stats.cells.max(1) as f64,
                stats.cells,
                stats.evaluated
            ),
        });
        // An edit of one solid: each run meshes the tree with one control value of one volume
        // other than the run before, keeping the blocks of the last mesh the edit cannot change.
        let edits = [tree_with(0.0), tree_with(0.05)];
        let mut cache = MeshCache::new();
        let mut which = 0;
        let mut remesh = |which: usize| {
            edits[which]
                .polygonize_share_cached(n, 1e-9, None, Share::WHOLE, &mut cache)
                .unwrap_or_else(|_| unreachable!("valid arguments"))
        };
        let _ = remesh(1);
        let (ms, runs, (triangles, made)) = time(clock, budget, || {
            which ^= 1;
            let (piece, made) = remesh(which);
            (piece.mesh.triangle_count(), made)
        });
        // The first mesh of a model: a cache that holds nothing, filled on the way.
        let (cold, cold_runs, _) = time(clock, budget, || {
            let mut empty = MeshCache::new();
            edits[0]
                .polygonize_share_cached(n, 1e-9, None, Share::WHOLE, &mut empty)
                .map(|(piece, _)| piece.mesh.triangle_count())
                .unwrap_or_else(|_| unreachable!("valid arguments"))
        });
        rows.push(Row {
            case: "tree of 20 solids: polygonize".into(),
            who: "bezsolid keeping its blocks for the next edit (the first mesh, cache empty)"
                .into(),
            n,
            ms: cold,
            runs: cold_runs,
            extra: triangles as f64,
            note: String::new(),
        });
        rows.push(Row {
            case: "tree of 20 solids: polygonize".into(),
            who: "bezsolid after an edit of one solid (blocks the edit cannot change kept)".into(),
            n,
            ms,
            runs,
            extra: triangles as f64,
            note: format!(
                "{:.1} % of {} blocks kept",
                100.0 * made.kept as f64 / made.blocks.max(1) as f64,
                made.blocks
            ),
        });
    }
    rows
}
