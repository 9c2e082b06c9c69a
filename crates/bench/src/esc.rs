//! The free-form cases: point-in-solid on the solids bounded by PN triangles, the extended
//! simplicial chain against Jordan ray parity on the same PN surface and the same grid (the paper's
//! Fig. 20 claim, as queries per second and patch intersections per query).

use bezsolid_core::esc::Boolean;
use bezsolid_core::esc::Example;
use bezsolid_core::esc::{EscSolid, Stats};
use bezsolid_core::esc::{Expr, Op};
use glam::DVec3;

use crate::inverse::Rng;
use crate::{Clock, Row, time};

/// Uniform random points in the solid's box enlarged by 10% (xorshift, fixed seed).
fn points(solid: &EscSolid, count: usize) -> Vec<DVec3> {
    let (lo, hi) = solid.bounds();
    let pad = (hi - lo) * 0.1;
    let (lo, hi) = (lo - pad, hi + pad);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut unit = move || rng.unit();
    (0..count)
        .map(|_| {
            DVec3::new(
                lo.x + (hi.x - lo.x) * unit(),
                lo.y + (hi.y - lo.y) * unit(),
                lo.z + (hi.z - lo.z) * unit(),
            )
        })
        .collect()
}

fn note(stats: &Stats, inside: usize, count: usize) -> String {
    let q = stats.queries.max(1) as f64;
    format!(
        "{:.4} patch intersections per query; {:.2} tetrahedra tested per query; {} re-cast rays; {} of {count} points inside",
        stats.patch_intersections as f64 / q,
        stats.tetrahedra as f64 / q,
        stats.retries,
        inside
    )
}

/// The point-in-solid cases, one per built-in example.
pub fn suite(clock: &mut dyn Clock, quick: bool) -> Vec<Row> {
    let budget = if quick { 50.0 } else { 1000.0 };
    let count = if quick { 2_000 } else { 200_000 };
    let mut rows = Vec::new();
    let mut cases: Vec<(String, bezsolid_core::mesh::Mesh)> = Example::ALL
        .iter()
        .map(|e| (e.name().to_owned(), e.mesh()))
        .collect();
    // The blob far from the origin: there the paper's apex sees it in a narrow cone.
    let mut far = Example::Blob.mesh();
    for p in &mut far.positions {
        *p += DVec3::splat(20.0);
    }
    cases.push(("blob moved by (20, 20, 20)".to_owned(), far));
    for (name, mesh) in cases {
        let n = mesh.triangles.len();
        let case = format!("point-in-solid: {name} ({n} triangles)");
        let solid = EscSolid::new(&mesh).unwrap_or_else(|_| unreachable!("a valid example"));
        let origin = EscSolid::with_apex(&mesh, DVec3::ZERO)
            .unwrap_or_else(|_| unreachable!("a valid example"));
        let queries = points(&solid, count);
        let mut row = |who: &str, test: &dyn Fn(DVec3, &mut Stats, &mut Vec<u32>) -> i32| {
            let (ms, runs, (stats, answers)) = time(clock, budget, || {
                let (mut stats, mut seen) = (Stats::default(), Vec::new());
                let answers: Vec<i32> = queries
                    .iter()
                    .map(|&q| test(q, &mut stats, &mut seen))
                    .collect();
                (stats, answers)
            });
            let inside = answers.iter().filter(|&&a| a == 1).count();
            let row = Row {
                case: case.clone(),
                who: who.into(),
                n,
                ms,
                runs,
                extra: count as f64 / (ms / 1000.0),
                note: note(&stats, inside, count),
            };
            (row, answers)
        };
        let (esc, esc_answers) = row("bezsolid: ESC (apex chosen)", &|q, stats, _| {
            solid.value(q, stats)
        });
        let (paper, paper_answers) = row(
            "bezsolid: ESC, apex at the origin (the paper's)",
            &|q, stats, _| origin.value(q, stats),
        );
        assert_eq!(
            esc_answers, paper_answers,
            "the apex does not change the solid"
        );
        let (mut parity, parity_answers) = row(
            "ray parity (Jordan), same PN surface and grid",
            &|q, stats, seen| solid.parity_value(q, stats, seen),
        );
        // Where the two tests disagree (none, when both are right).
        let differ = esc_answers
            .iter()
            .zip(&parity_answers)
            .filter(|(a, b)| a != b)
            .count();
        parity.note = format!("{}; differs from ESC on {differ} points", parity.note);
        rows.extend([esc, paper, parity]);
    }
    // The modeler's result surface: the blob minus a torus through it, by marching cubes on the
    // chain's membership with vertices where grid edges cross the PN surfaces.
    let blob = EscSolid::new(&Example::Blob.mesh()).unwrap_or_else(|_| unreachable!("valid"));
    let mut torus = Example::Torus.mesh();
    for p in &mut torus.positions {
        p.z += 0.35;
    }
    let torus = EscSolid::new(&torus).unwrap_or_else(|_| unreachable!("valid"));
    let boolean = Boolean {
        solids: vec![blob, torus],
        expr: Expr::binary(Op::Difference, Expr::Solid(0), Expr::Solid(1)),
    };
    let surface = "closed result mesh of blob − torus (the export; exact edge crossings)";
    let sizes: &[usize] = if quick { &[24] } else { &[24, 64, 128] };
    for &res in sizes {
        let (ms, runs, mesh) = time(clock, budget, || boolean.surface(res));
        rows.push(Row {
            case: surface.into(),
            who: "bezsolid".into(),
            n: res,
            ms,
            runs,
            extra: mesh.triangles.len() as f64,
            note: String::new(),
        });
    }
    // Meshes as they are imported: few, large triangles with sharp edges, whose PN patches bulge
    // far from them (thick free-form cells): the unit cube of the test fixtures minus an
    // octahedron about one of its corners.
    let read = |text: &str| {
        let mesh = bezsolid_core::mesh::read(text.as_bytes())
            .unwrap_or_else(|_| unreachable!("a closed mesh"));
        EscSolid::new(&mesh).unwrap_or_else(|_| unreachable!("valid"))
    };
    let octahedron = "v 1.4 0 0\nv -1.4 0 0\nv 0 1.4 0\nv 0 -1.4 0\nv 0 0 1.4\nv 0 0 -1.4\n\
                      f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
    let imported = Boolean {
        solids: vec![
            read(include_str!("../../core/tests/fixtures/mesh/cube.obj")),
            read(octahedron),
        ],
        expr: Expr::binary(Op::Difference, Expr::Solid(0), Expr::Solid(1)),
    };
    let sizes: &[usize] = if quick { &[24] } else { &[64, 160] };
    for &res in sizes {
        let (ms, runs, mesh) = time(clock, budget, || imported.surface(res));
        rows.push(Row {
            case: "closed result mesh of an imported cube − octahedron (12 and 8 triangles, sharp edges)".into(),
            who: "bezsolid".into(),
            n: res,
            ms,
            runs,
            extra: mesh.triangles.len() as f64,
            note: String::new(),
        });
    }
    let trimmed = "trimmed PN surfaces of blob − torus (the page's view at rest; n = triangles per patch edge)";
    let levels: &[usize] = if quick { &[1] } else { &[1, 4] };
    for &level in levels {
        let (ms, runs, mesh) = time(clock, budget, || boolean.trimmed_surface(level));
        rows.push(Row {
            case: trimmed.into(),
            who: "bezsolid".into(),
            n: level,
            ms,
            runs,
            extra: mesh.triangles.len() as f64,
            note: String::new(),
        });
    }
    let (ms, runs, points) = time(clock, budget, || boolean.point_mesh(25));
    rows.push(Row {
        case: "point mesh of blob − torus (the paper's 25³ view)".into(),
        who: "bezsolid".into(),
        n: 25,
        ms,
        runs,
        extra: (points.inside.len() + points.marked.len()) as f64,
        note: String::new(),
    });

    // What importing a mesh costs before the first query: PN patches, apex, cube map, walls, grid.
    let build = "build the chain of a mesh (PN patches, apex, cube map, walls, grid)";
    let sizes: &[u32] = if quick { &[3] } else { &[3, 4, 6] };
    for &level in sizes {
        let mesh = bezsolid_core::esc::examples::icosphere(level);
        let (ms, runs, solid) = time(clock, budget, || {
            EscSolid::new(&mesh).unwrap_or_else(|_| unreachable!("a valid icosphere"))
        });
        rows.push(Row {
            case: build.into(),
            who: "bezsolid: icosphere".into(),
            n: solid.triangles().len(),
            ms,
            runs,
            extra: solid.triangles().len() as f64,
            note: String::new(),
        });
    }
    rows
}
