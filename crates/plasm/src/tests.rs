//! The paper's scripts, run verbatim, against the mathematics they stand for.

use bezsolid_core::blend::{self, Fun as Map, Handle};
use bezsolid_core::{BezierCurve, blend::patch_from_curves};
use glam::{DVec2, DVec3};

use super::*;
use crate::scripts::*;

/// Runs scripts in one interpreter, failing on any error.
fn run(parts: &[&str]) -> (Interp, Vec<Shown>) {
    let mut p = Interp::new();
    let mut shown = Vec::new();
    for src in parts {
        let r = p.run(src);
        if let Some(e) = r.error {
            panic!("{e}\nin:\n{src}");
        }
        shown.extend(r.shown);
    }
    (p, shown)
}

fn pol(s: &Shown) -> &Complex {
    s.value.as_pol().expect("a complex")
}

/// Evaluates a script's map (a function, or a sequence of coordinate functions) at a point.
fn at(p: &mut Interp, name: &str, x: &[f64]) -> Vec<f64> {
    let f = p
        .global(name)
        .unwrap_or_else(|| panic!("{name} defined"))
        .clone();
    p.call(&f, x)
        .unwrap_or_else(|e| panic!("{name} at {x:?}: {e}"))
        .as_point()
        .unwrap_or_else(|| panic!("{name} gives a point"))
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn script_3_1_arcs_lie_on_the_unit_circle() {
    let (_, shown) = run(&[S3_2.text, S3_1.text]);
    assert_eq!(shown.len(), 3);
    let maps: [fn(f64) -> [f64; 2]; 3] = [
        |u| {
            let t = std::f64::consts::FRAC_PI_2 * u;
            [t.cos(), t.sin()]
        },
        |u| [(1.0 - u * u) / (1.0 + u * u), 2.0 * u / (1.0 + u * u)],
        |u| [u, (1.0 - u * u).sqrt()],
    ];
    for (s, map) in shown.iter().zip(maps) {
        let c = pol(s);
        assert_eq!(
            (c.dim, c.order, c.point_count(), c.cell_count()),
            (2, 2, 11, 10)
        );
        for i in 0..11 {
            let p = c.point(i);
            assert!(
                (p[0].hypot(p[1]) - 1.0).abs() < 1e-12,
                "{p:?} off the circle"
            );
            // The toolbox's interval is T:1:0 of QUOTE: the points are k/10, as summed.
            let u = (0..i).fold(0.0, |s, _| s + 0.1);
            assert!(close(p, &map(u), 1e-12), "{p:?} against {:?}", map(u));
        }
        // Consecutive points are joined.
        assert!((0..10).all(|k| c.cell(k) == [k as u32, k as u32 + 1]));
    }
}

#[test]
fn script_3_3_reverses_the_quarter_circle() {
    let (_, shown) = run(&[S3_2.text, S3_3.text]);
    let c = pol(&shown[0]);
    assert_eq!((c.point_count(), c.cell_count()), (21, 20));
    for i in 0..21 {
        let u = (0..i).fold(0.0, |s, _| s + 0.05);
        let t = std::f64::consts::FRAC_PI_2 * (1.0 - u);
        assert!(close(c.point(i), &[t.cos(), t.sin()], 1e-12));
    }
    assert!(close(c.point(0), &[0.0, 1.0], 1e-12));
    assert!(close(c.point(20), &[1.0, 0.0], 1e-12));
}

#[test]
fn script_4_1_is_the_cubic_bezier_curve() {
    let (mut p, _) = run(&[S4_1.text, "DEF q = Bezier3:<<0,0>,<1,2>,<3,2>,<4,-1>>;"]);
    let curve = BezierCurve::try_new(vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 2.0),
        DVec2::new(3.0, 2.0),
        DVec2::new(4.0, -1.0),
    ])
    .expect("a curve");
    for k in 0..=16 {
        let u = k as f64 / 16.0;
        let q = curve.eval(u);
        assert!(close(&at(&mut p, "q", &[u]), &[q.x, q.y], 1e-12));
    }
    // Bezier3 checks its parameters.
    let err = p
        .run("Bezier3:<<0,0>,<1,2>,<3,2>,<4,TRUE>>;")
        .error
        .expect("a type error");
    assert_eq!(err.kind, ErrorKind::Type);
    assert!(err.message.contains("p3"), "{err}");
}

fn curves_4_4() -> [BezierCurve<DVec3>; 4] {
    let c = |pts: &[[f64; 3]]| {
        BezierCurve::try_new(pts.iter().map(|p| DVec3::from_array(*p)).collect()).expect("a curve")
    };
    [
        c(&[[0., 0., 0.], [10., 0., 0.]]),
        c(&[[0., 2., 0.], [8., 3., 0.], [9., 2., 0.]]),
        c(&[[0., 4., 1.], [7., 5., -1.], [8., 5., 1.], [12., 4., 0.]]),
        c(&[[0., 6., 0.], [9., 6., 3.], [10., 6., -1.]]),
    ]
}

#[test]
fn script_4_4_surface_is_the_blend_of_its_curves() {
    let mut p = Interp::new();
    let mut warnings = Vec::new();
    for s in [S4_2, S4_3, S4_4] {
        let r = p.run(s.text);
        assert!(r.error.is_none(), "{}", r.error.expect("an error"));
        warnings.extend(r.warnings);
        if s.number == "4.4" {
            let c = pol(&r.shown[0]);
            assert_eq!(
                (c.dim, c.order, c.point_count(), c.cell_count()),
                (3, 3, 441, 800)
            );
        }
    }
    // The two damaged readings are said: Bernstein's `~` and Script 4.4's point lists.
    assert_eq!(warnings.len(), 5, "{warnings:?}");
    assert!(warnings[0].message.contains("read as `* ~`"));
    assert_eq!(warnings[0].span.line, 6);
    let curves = curves_4_4();
    let binomial = [1.0, 3.0, 3.0, 1.0];
    for i in 0..=8 {
        for j in 0..=8 {
            let (u1, u2) = (i as f64 / 8.0, j as f64 / 8.0);
            // Σ C_i(u1) β_i³(u2)
            let want = (0..4).fold(DVec3::ZERO, |s, k| {
                s + curves[k].eval(u1)
                    * binomial[k]
                    * u2.powi(k as i32)
                    * (1.0 - u2).powi(3 - k as i32)
            });
            let got = at(&mut p, "Surf1", &[u1, u2]);
            assert!(
                close(&got, &want.to_array(), 1e-10),
                "{got:?} ≠ {want} at ({u1}, {u2})"
            );
            // Each curve on its own, too.
            let c = at(&mut p, "C2", &[u1]);
            assert!(close(&c, &curves[2].eval(u1).to_array(), 1e-12));
        }
    }
    // The core's blend of the same handles agrees.
    let handles: Vec<Handle> = curves
        .iter()
        .map(|c| {
            let pts: Vec<[f64; 3]> = c.points().iter().map(|p| p.to_array()).collect();
            let hs: Vec<Handle> = pts.iter().map(|q| Handle::point(q)).collect();
            Handle::Map(blend::bezier(&Map::select(0), &hs).expect("a curve"))
        })
        .collect();
    let surface = blend::bezier(&Map::select(1), &handles).expect("a surface");
    let x = [0.3, 0.7];
    assert!(close(
        &at(&mut p, "Surf1", &x),
        &blend::eval(&surface, &x),
        1e-12
    ));
}

#[test]
fn blend_of_equal_degree_curves_is_the_tensor_patch() {
    // Four cubic curves, blended by the script and built as a patch from the same points.
    let pts = |i: usize| -> Vec<DVec3> {
        (0..4)
            .map(|j| DVec3::new(j as f64, i as f64, ((i * 3 + j * 5) % 7) as f64 - 3.0))
            .collect()
    };
    let mut src = String::new();
    for i in 0..4 {
        let list: Vec<String> = pts(i)
            .iter()
            .map(|p| format!("<{},{},{}>", p.x, p.y, p.z))
            .collect();
        src.push_str(&format!("DEF K{i} = Bezier:S1:<{}>;\n", list.join(",")));
    }
    src.push_str("DEF Surf = Bezier:S2:<K0,K1,K2,K3>;");
    let (mut p, _) = run(&[S4_2.text, S4_3.text, &src]);
    let curves: Vec<BezierCurve<DVec3>> = (0..4)
        .map(|i| BezierCurve::try_new(pts(i)).expect("a curve"))
        .collect();
    let patch = patch_from_curves(&curves).expect("a patch");
    for (u1, u2) in [(0.0, 0.0), (0.25, 0.5), (0.9, 0.1), (1.0, 1.0), (0.5, 0.75)] {
        // The blend at (u1, u2) is the patch at (u, v) = (u2, u1).
        let want = patch.eval([u2, u1]);
        assert!(close(
            &at(&mut p, "Surf", &[u1, u2]),
            &want.to_array(),
            1e-12
        ));
    }
}

/// Hermite basis, for the expected values.
fn eta(v: f64) -> [f64; 4] {
    [
        2.0 * v.powi(3) - 3.0 * v * v + 1.0,
        3.0 * v * v - 2.0 * v.powi(3),
        v.powi(3) - 2.0 * v * v + v,
        v.powi(3) - v * v,
    ]
}

fn derivative(p: &mut Interp, name: &str, x: [f64; 2], axis: usize) -> Vec<f64> {
    // One-sided at the ends of [0, 1], second-order accurate.
    let h = 1e-5;
    let s = if x[axis] > 0.5 { -1.0 } else { 1.0 };
    let mut pts = [x; 3];
    pts[1][axis] += s * h;
    pts[2][axis] += 2.0 * s * h;
    let f: Vec<Vec<f64>> = pts.iter().map(|q| at(p, name, q)).collect();
    (0..f[0].len())
        .map(|d| s * (-3.0 * f[0][d] + 4.0 * f[1][d] - f[2][d]) / (2.0 * h))
        .collect()
}

#[test]
fn scripts_4_6_and_4_7_interpolate_curves_and_tangents() {
    let (mut p, shown) = run(&[S4_5.text, S4_8.text, S4_6.text, S4_7.text]);
    assert_eq!(shown.len(), 2);
    for s in &shown {
        let c = pol(s);
        assert_eq!(
            (c.dim, c.order, c.point_count(), c.cell_count()),
            (3, 3, 225, 392)
        );
    }
    // c1 and c2: H(0) = p0, H(1) = p1, H'(0) = t0, H'(1) = t1.
    for (name, p0, p1, t0, t1) in [
        ("c1", [1.0, 0.0], [0.0, 1.0], [0.0, 3.0], [-3.0, 0.0]),
        ("c2", [0.5, 0.0], [0.0, 0.5], [0.0, 1.0], [-1.0, 0.0]),
    ] {
        assert!(close(&at(&mut p, name, &[0.0]), &p0, 1e-12));
        assert!(close(&at(&mut p, name, &[1.0]), &p1, 1e-12));
        let d = |p: &mut Interp, u: f64| {
            let e = derivative(p, name, [u, 0.0], 0);
            e[..2].to_vec()
        };
        assert!(close(&d(&mut p, 0.0), &t0, 1e-6));
        assert!(close(&d(&mut p, 1.0), &t1, 1e-6));
    }
    for (surf, t0, t1) in [
        ("Surf2", [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]),
        ("Surf3", [1.0, 1.0, 1.0], [-1.0, -1.0, -1.0]),
    ] {
        for k in 0..=10 {
            let u = k as f64 / 10.0;
            let c1 = at(&mut p, "c1", &[u]);
            let c2 = at(&mut p, "c2", &[u]);
            // The plane curves blend as if at z = 0.
            assert!(close(
                &at(&mut p, surf, &[u, 0.0]),
                &[c1[0], c1[1], 0.0],
                1e-12
            ));
            assert!(close(
                &at(&mut p, surf, &[u, 1.0]),
                &[c2[0], c2[1], 0.0],
                1e-12
            ));
            assert!(close(&derivative(&mut p, surf, [u, 0.0], 1), &t0, 1e-6));
            assert!(close(&derivative(&mut p, surf, [u, 1.0], 1), &t1, 1e-6));
            // Inside: c1 η0 + c2 η1 + t0 η2 + t1 η3.
            let v = 0.37;
            let e = eta(v);
            let (a, b) = (at(&mut p, "c1", &[u]), at(&mut p, "c2", &[u]));
            let want: Vec<f64> = (0..3)
                .map(|d| {
                    let (x, y) = (
                        a.get(d).copied().unwrap_or(0.0),
                        b.get(d).copied().unwrap_or(0.0),
                    );
                    x * e[0] + y * e[1] + t0[d] * e[2] + t1[d] * e[3]
                })
                .collect();
            assert!(close(&at(&mut p, surf, &[u, v]), &want, 1e-12));
        }
    }
}

#[test]
fn script_4_8_grid1_is_the_linear_blend() {
    let (mut p, _) = run(&[S4_2.text, S4_3.text, S4_5.text, S4_8.text]);
    let samples: Vec<[f64; 2]> = (0..=6)
        .flat_map(|i| (0..=6).map(move |j| [i as f64 / 6.0, j as f64 / 6.0]))
        .collect();
    let hermite: Vec<Vec<f64>> = samples.iter().map(|x| at(&mut p, "grid1", x)).collect();
    let grid2: Vec<Vec<f64>> = samples.iter().map(|x| at(&mut p, "grid2", x)).collect();
    // The lines after Fig. 4 redefine grid1 as Bezier:S2:<c1, c2>.
    let r = p.run(S4_7_BEZIER_GRID.text);
    assert!(r.error.is_none());
    let c = pol(&r.shown[0]);
    assert_eq!((c.dim, c.point_count(), c.cell_count()), (2, 81, 128));
    for (x, h) in samples.iter().zip(&hermite) {
        let bezier = at(&mut p, "grid1", x);
        assert!(close(h, &bezier, 1e-12), "{h:?} ≠ {bezier:?} at {x:?}");
        // And both are (1 − v) c1(u) + v c2(u).
        let (c1, c2) = (at(&mut p, "c1", &[x[0]]), at(&mut p, "c2", &[x[0]]));
        let lin: Vec<f64> = (0..2)
            .map(|d| (1.0 - x[1]) * c1[d] + x[1] * c2[d])
            .collect();
        assert!(close(h, &lin, 1e-12));
    }
    // grid2 has the tangent <-0.5, -0.5> along c1: not the linear blend inside.
    assert!(
        samples
            .iter()
            .zip(&grid2)
            .zip(&hermite)
            .any(|((x, g), h)| { x[1] > 0.0 && x[1] < 1.0 && !close(g, h, 1e-3) })
    );
    let d = derivative(&mut p, "grid2", [0.5, 0.0], 1);
    assert!(close(&d, &[-0.5, -0.5], 1e-6));
}

#[test]
fn the_bezier_grid_example_draws_fig_4s_grid1() {
    // The menu's example of the lines after Fig. 4 draws what Fig. 4's grid1 (as Hermite) is: the
    // same cells on the same points.
    let drawn = |id: &str| {
        let r = Interp::new().run(&scripts::example(id).expect("an example").source());
        assert!(r.error.is_none(), "{id}: {:?}", r.error);
        r.shown
            .iter()
            .filter_map(|s| s.value.as_pol())
            .map(|c| (c.dim, c.order, c.cells.clone(), c.points.clone()))
            .collect::<Vec<_>>()
    };
    let bezier = drawn("4.7-bezier-grid");
    let fig4 = drawn("4.8");
    assert_eq!(bezier.len(), 1);
    let ((dim, order, cells, points), (dim4, order4, cells4, points4)) = (&bezier[0], &fig4[0]);
    assert_eq!((dim, order, cells.len()), (&2, &3, 128 * 3));
    assert_eq!((dim, order, cells), (dim4, order4, cells4));
    assert_eq!(points.len(), points4.len());
    for (a, b) in points.iter().zip(points4) {
        assert!((a - b).abs() < 1e-12, "{a} ≠ {b}");
    }
}

#[test]
fn every_example_runs_and_draws() {
    for e in scripts::EXAMPLES {
        let mut p = Interp::new();
        let r = p.run(&e.source());
        assert!(
            r.error.is_none(),
            "{}: {}",
            e.id,
            r.error.expect("an error")
        );
        let complexes: Vec<&Complex> = r.shown.iter().filter_map(|s| s.value.as_pol()).collect();
        assert!(!complexes.is_empty(), "{} draws nothing", e.id);
        let g = mesh::Geometry::of(complexes.iter().copied());
        assert!(!g.is_empty());
        // The OBJ names every point and cell.
        let obj = mesh::write_obj(complexes.iter().copied());
        let v = obj.lines().filter(|l| l.starts_with("v ")).count();
        assert_eq!(v, complexes.iter().map(|c| c.point_count()).sum::<usize>());
    }
}

fn error(src: &str) -> Error {
    let mut p = Interp::new();
    p.run(src)
        .error
        .unwrap_or_else(|| panic!("no error from {src}"))
}

#[test]
fn malformed_scripts_give_located_errors() {
    let cases: &[(&str, ErrorKind, u32, u32, &str)] = &[
        (
            "DEF a = <1, 2;\n",
            ErrorKind::Syntax,
            1,
            14,
            "closing the list",
        ),
        ("DEF a = (1 + 2;", ErrorKind::Syntax, 1, 15, "`)`"),
        ("DEF a = [ID, ID;", ErrorKind::Syntax, 1, 16, "`]`"),
        (
            "DEF a = 1 + 2)\n;",
            ErrorKind::Syntax,
            1,
            14,
            "expected `;`",
        ),
        (
            "\n  MAP:(CONS:alhpa ~ S1):(Domain:4);",
            ErrorKind::Name,
            2,
            13,
            "unknown name `alhpa`",
        ),
        (
            "DEF Surfce = 1;\nSurface:S1;",
            ErrorKind::Name,
            2,
            1,
            "did you mean `Surfce`",
        ),
        ("1 + <1, 2>;", ErrorKind::Type, 1, 3, "a sequence of 2"),
        ("SIN:ID;", ErrorKind::Type, 1, 1, "SIN ~ f"),
        ("3:4;", ErrorKind::Type, 1, 1, "not a function"),
        (
            "DEF f (n::IsNat) = n;\nf:(-1);",
            ErrorKind::Type,
            2,
            1,
            "does not satisfy",
        ),
        (
            "MAP:<SIN, 2>:(Domain:2);",
            ErrorKind::Type,
            1,
            1,
            "must be a function",
        ),
        (
            "MAP:(K:<SIN>):(Domain:2);",
            ErrorKind::Type,
            1,
            1,
            "not a point",
        ),
        ("1/0;", ErrorKind::Math, 1, 2, "division by zero"),
        (
            "MAP:(CONS:<LN ~ S1>):(Domain:2);",
            ErrorKind::Math,
            1,
            1,
            "LN:0",
        ),
        (
            "DEF f (n::IsReal) = f:(n + 1);\nf:0;",
            ErrorKind::Limit,
            1,
            21,
            "nested more than",
        ),
        (
            "MAP:(CONS:<S1, S2>):(Domain:10000 * Domain:10000);",
            ErrorKind::Limit,
            1,
            35,
            "200000000 cells",
        ),
        ("#:100000000:1;", ErrorKind::Limit, 1, 1, "100000000 items"),
        (
            "DEF big = #:1000000:1;\nDEF f (x::IsReal) = AA:ID:big;\nAA:f:big;",
            ErrorKind::Limit,
            2,
            21,
            "stopped after",
        ),
        (
            "DEF a = b WHERE b = c, c = b END;",
            ErrorKind::Name,
            1,
            28,
            "in terms of itself",
        ),
        ("DEF x = 'text';", ErrorKind::Syntax, 1, 9, "strings"),
        (
            "MAP:(K:<>):(Domain:2);",
            ErrorKind::Type,
            1,
            1,
            "an empty point",
        ),
        (
            "MAP:[]:(Domain:2);",
            ErrorKind::Type,
            1,
            1,
            "an empty point",
        ),
    ];
    for &(src, kind, line, col, words) in cases {
        let e = error(src);
        assert_eq!(
            (e.kind, e.span.line, e.span.col),
            (kind, line, col),
            "{src:?} gave {e}"
        );
        assert!(e.message.contains(words), "{src:?} gave {e}");
    }
}

/// Runs `f` on a thread with a 1 MiB stack, as small as a wasm module's default; unoptimised
/// frames are several times larger, so the debug build gets 16 MiB. (The page's own module is
/// checked the same way in node, tests/node.)
fn in_small_stack(f: impl FnOnce() + Send + 'static) {
    let stack = if cfg!(debug_assertions) {
        16 << 20
    } else {
        1 << 20
    };
    std::thread::Builder::new()
        .stack_size(stack)
        .spawn(f)
        .expect("a thread")
        .join()
        .expect("no overflow");
}

#[test]
fn deep_nesting_is_refused_not_overflowed() {
    in_small_stack(deep_nesting);
}

fn deep_nesting() {
    let deep = "(".repeat(300) + "1" + &")".repeat(300) + ";";
    assert_eq!(error(&deep).kind, ErrorKind::Limit);
    let seq = "<".repeat(300) + &">".repeat(300) + ";";
    assert_eq!(error(&seq).kind, ErrorKind::Limit);
    // Long chains nest as deeply as brackets (and would be dropped as deeply).
    for chain in [
        "1".to_string() + &"-1".repeat(20_000) + ";",
        "ID".to_string() + &":1".repeat(20_000) + ";",
        "1".to_string() + &"*1".repeat(20_000) + ";",
    ] {
        let e = error(&chain);
        assert_eq!((e.kind, e.span.line), (ErrorKind::Limit, 1), "{e}");
    }
    // A long composition is one node: fine.
    assert!(
        Interp::new()
            .run(&("ID".to_string() + &" ~ ID".repeat(5_000) + ";"))
            .error
            .is_none()
    );
    // Values deepened statement after statement are dropped without recursion, and compared
    // and shown within bounds.
    let mut src = String::from("DEF a0 = S1;\n");
    for i in 1..=60 {
        src.push_str(&format!("DEF a{i} = a{} {};\n", i - 1, "- 1 ".repeat(200)));
    }
    src.push_str("a60;\nMAP:[a60]:(interval:<0,1>:1);\n");
    let r = Interp::new().run(&src);
    let e = r.error.expect("too deep to apply");
    assert_eq!(e.kind, ErrorKind::Limit);
    assert!(r.shown[0].value.to_string().len() < 1000);
    let mut src = String::from("DEF s0 = 1;\nDEF r0 = 1;\n");
    for i in 1..=200 {
        for name in ["s", "r"] {
            let (open, close) = ("<".repeat(50), ">".repeat(50));
            src.push_str(&format!("DEF {name}{i} = {open}{name}{}{close};\n", i - 1));
        }
    }
    src.push_str("EQ:<s200, s200>;\nEQ:<s200, r200>;\n");
    let r = Interp::new().run(&src);
    assert_eq!(
        r.shown[0].value.to_string(),
        "TRUE",
        "the same sequence, at once"
    );
    assert_eq!(r.error.map(|e| e.kind), Some(ErrorKind::Limit));
}

#[test]
fn recursion_stops_within_a_small_stack() {
    // The depth limits must stop recursion before the stack does: run the worst recursions on a
    // thread with a 1 MiB stack, as small as a wasm module's default.
    let cases = [
        "DEF f (n::IsReal) = f:(n + 1);\nf:0;",
        "DEF g (n::IsReal) = IF:<K:FALSE, ID, g ~ K:(n + 1)>:n;\ng:0;",
        "DEF h (x::IsReal) = (h ~ ID ~ ID ~ ID):x;\nh:1;",
        // Deep expressions inside each call.
        "DEF s (n::IsReal) = <<<<<<<<<<<<<<<<<<<<<<<<s:(n + 1)>>>>>>>>>>>>>>>>>>>>>>>>;\ns:0;",
        "DEF p (n::IsReal) = 1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(1+(p:(n+1)))))))))))))))));\np:0;",
        "DEF Pred = C:-:1;\nDEF Choose (n,k::IsNat) = IF:<OR ~ [C:EQ:0 ~ S2, EQ], K:1, Choose ~ AA:Pred * / >:<n,k>;\nChoose:<1000, 999>;",
    ];
    in_small_stack(move || {
        for src in cases {
            let e = error(src);
            assert_eq!(e.kind, ErrorKind::Limit, "{e}");
        }
    });
}

#[test]
fn choose_and_fact_compute() {
    let (mut p, _) = run(&[S4_2.text]);
    let r = p.run("Choose:<5, 2>; Choose:<10, 0>; (Fact:3):4; Pred:7; BernsteinBasis:S1:3;");
    assert!(r.error.is_none(), "{:?}", r.error);
    let v: Vec<String> = r.shown.iter().map(|s| s.value.to_string()).collect();
    assert_eq!(v[..4], ["10", "1", "24", "6"]);
    assert!(v[4].starts_with('<'), "{}", v[4]);
}

#[test]
fn garbage_never_panics() {
    // Random token soups from the language's own pieces: every run ends, with or without an
    // error.
    let pieces = [
        "DEF",
        "f",
        "(",
        ")",
        "<",
        ">",
        "[",
        "]",
        ",",
        ";",
        ":",
        "::",
        "~",
        "=",
        "+",
        "-",
        "*",
        "/",
        "**",
        "..",
        "1",
        "0",
        "-2.5",
        "ID",
        "K",
        "AA",
        "MAP",
        "CONS",
        "S1",
        "S3",
        "TRANS",
        "IF",
        "EQ",
        "Domain:3",
        "QUOTE",
        "T",
        "WHERE",
        "END",
        "#",
        "INTSTO",
        "IsReal",
        "SEL",
        "DISTL",
        "InnerProd",
        "C",
        "LEN",
        "Intervals",
        "interval",
        "PI",
        "SIN",
        "SQRT",
    ];
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    for _ in 0..3000 {
        let mut src = String::new();
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let len = 1 + (seed % 24) as usize;
        for _ in 0..len {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            src.push_str(pieces[(seed % pieces.len() as u64) as usize]);
            src.push(' ');
        }
        let mut p = Interp::with_limits(Limits {
            steps: 200_000,
            ..Limits::default()
        });
        let _ = p.run(&src);
    }
}

#[test]
fn compiled_maps_give_the_interpreters_points_to_the_bit() {
    let interpreted = Limits {
        kernels: false,
        ..Limits::default()
    };
    let extra = [
        // Arithmetic of every kind, math functions, C, AA, SEL and constants in a map.
        "MAP:[S1, SIN ~ S2, (K:2 ** S1) - (S2 / K:3), C:-:1 ~ S1, + ~ AA:SQRT, \
         ABS ~ (K:0.5 - S1) * ATAN ~ S2, SEL:2 ~ [S2, EXP ~ S1]]:(Domain:7 * Domain:5);",
        "MAP:(CONS:<K:1, - ~ [ID, K:0.25] ~ S1>):(interval:<-1, 2>:9);",
    ];
    let mut sources: Vec<String> = scripts::EXAMPLES.iter().map(|e| e.source()).collect();
    sources.extend(extra.iter().map(|s| (*s).to_string()));
    for src in &sources {
        let fast = Interp::new().run(src);
        let slow = Interp::with_limits(interpreted).run(src);
        assert!(
            fast.error.is_none() && slow.error.is_none(),
            "{:?}",
            fast.error
        );
        assert!(fast.steps < slow.steps, "the kernel does less work");
        for (a, b) in fast.shown.iter().zip(&slow.shown) {
            let (Some(a), Some(b)) = (a.value.as_pol(), b.value.as_pol()) else {
                continue;
            };
            assert_eq!(a.dim, b.dim);
            assert!(
                a.points
                    .iter()
                    .zip(&b.points)
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "the same points, to the bit"
            );
            assert_eq!(a.cells, b.cells);
        }
    }
    // Where the kernel meets a value that is not finite, the interpreter's error stands.
    for (src, words) in [
        ("MAP:(CONS:<K:1 / S1>):(Domain:2);", "division by zero"),
        (
            "MAP:(CONS:<K:1 / (K:1 / S1)>):(Domain:2);",
            "division by zero",
        ),
        ("MAP:(CONS:<SQRT ~ (K:0.5 - S1)>):(Domain:2);", "SQRT:-0.5"),
        (
            "MAP:(CONS:<(ID ** K:0.5) ~ (K:0 - S1)>):(Domain:2);",
            "not a finite number",
        ),
    ] {
        let e = Interp::new().run(src).error.expect("an error");
        assert!(e.message.contains(words), "{src}: {e}");
    }
}

#[test]
fn work_and_memory_count_against_the_limits() {
    // Each of these once ran long or asked for gigabytes without reaching a limit.
    let doubling: String = std::iter::once("DEF f0 = ID;\n".to_string())
        .chain((1..=30).map(|i| format!("DEF f{i} = f{} + f{};\n", i - 1, i - 1)))
        .collect();
    let repeated_results: String = std::iter::once("DEF c = interval:<0,1>:999999;\n".to_string())
        .chain((0..30).map(|_| "c;\n".to_string()))
        .collect();
    let wide_cons = format!(
        "DEF f (x::IsNum) = [{}];\nAA:(K:0 ~ f):(1..2000);",
        vec!["ID"; 20_000].join(", ")
    );
    for src in [
        doubling.as_str(),
        "CAT:(#:1000000:(1..1000000));",
        "TRANS:(#:65536:(1..65536));",
        "MAP:(CONS:(#:1000:S1)):(interval:<0,1>:999999);",
        "DEF s = 1..1000000;\nAA:(+ ~ K:s):(1..300);",
        "DEF s = 1..1000000;\nAA:(TAIL ~ K:s):(1..300);",
        "DEF s = 1..1000000;\nAA:(REVERSE ~ K:s):(1..300);",
        "DEF a = #:1000:(1..1000);\nDEF b = #:1000:a;\nDEF c = #:1000:(1..1000);\nDEF d = #:1000:c;\nEQ:<b, d>;",
        wide_cons.as_str(),
        repeated_results.as_str(),
    ] {
        let e = Interp::new().run(src).error;
        assert_eq!(
            e.as_ref().map(|e| e.kind),
            Some(ErrorKind::Limit),
            "{}: {e:?}",
            &src[..src.len().min(60)]
        );
    }
    // Wide maps compile in linear time (or are interpreted), not quadratic.
    let wide = "DEF f = CONS:(#:20000:S1);\nDEF d = MAP:f:(interval:<0,1>:1);\nMAP:f:d;\nMAP:f:d;";
    assert!(Interp::new().run(wide).error.is_none());
    // A long script's value is shown briefly.
    let r = Interp::new().run("1..1000000;");
    assert!(r.shown[0].value.to_string().chars().count() < 200);
    // The source limit's error is at line 1.
    let big = " ".repeat(Limits::default().source + 1);
    let e = Interp::new().run(&big).error.expect("too long");
    assert_eq!((e.kind, e.span.line, e.span.col), (ErrorKind::Limit, 1, 1));
}

#[test]
fn memory_limit_stops_a_run_at_its_place() {
    // A range of 30,000 numbers holds 480 KB: two fit in 1 MiB, not three.
    let small = Limits {
        memory: 1 << 20,
        ..Limits::default()
    };
    let src = "DEF a = 1..30000;\nDEF b = 1..30000;\nDEF c = 1..30000;\nDEF d = 1..30000;";
    let r = Interp::with_limits(small).run(src);
    let e = r.error.expect("past the budget");
    assert_eq!((e.kind, e.span.line, e.span.col), (ErrorKind::Limit, 3, 10));
    assert_eq!(
        e.message,
        "the script builds more than 1 MiB of values held at once (sequences, functions, \
         complexes): past the memory limit"
    );
    assert!(r.memory > 960_000 && r.memory <= 1 << 20, "{}", r.memory);
}

#[test]
fn memory_is_given_back_as_values_are_dropped() {
    // A hundred ranges of 1.6 MB each, 160 MB in all, within 4 MiB: each is dropped once its
    // length is taken.
    let small = Limits {
        memory: 4 << 20,
        ..Limits::default()
    };
    let src = "DEF big (n::IsNat) = LEN:(1..100000);\n+:(AA:big:(1..100));";
    let r = Interp::with_limits(small).run(src);
    assert!(r.error.is_none(), "{:?}", r.error);
    assert_eq!(r.shown[0].value.as_num(), Some(1e7));
    assert!(r.memory > 1_600_000 && r.memory < 4 << 20, "{}", r.memory);
}

#[test]
fn memory_charged_by_a_run_is_all_given_back() {
    // Every byte counted as built is credited as dropped, whether the run ends well or not,
    // halfway through filling a buffer, or in a call after the run.
    let start = crate::meter::live();
    let mut sources: Vec<String> = scripts::EXAMPLES.iter().map(|e| e.source()).collect();
    sources.extend(
        [
            "DEF h (x::IsReal) = g:x;\nDEF g = CONS:(AL:<h, #:9999:ID>);\ng:0;",
            "DEF h (x::IsReal) = g:x;\nDEF g = +:(AL:<h, #:9999:ID>);\ng:0;",
            "DEF a = T:3:0:(interval:<0,1>:50);\nDEF p = a * a * interval:<0,1>:3;\nMAP:[S1, S6]:p;",
            "MAP:(CONS:(#:40:S1)):(interval:<0,1>:9999);",
            "DEF f (n::IsNat) = <n, k> WHERE k = n * 2, j = k END;\nAA:f:(1..100);",
            "TRANS:<1..100, DISTL:<0, 1..300>>; TAIL:(1..10); REVERSE:(1..10); QUOTE:<1,-1,2>;",
            "S:2:3:(T:<1, 2>:<1, 1>:(Domain:4 * Domain:5)); InnerProd:<<ID, K:2>, <S1, S2>>;",
            "[ID, ID ~ SIN, ID ~ (COS ~ ID)]:1; AA:(1 / ID):<1, 0>;",
        ]
        .map(String::from),
    );
    for src in &sources {
        let memory = Limits {
            memory: 8 << 20,
            ..Limits::default()
        };
        for limits in [Limits::default(), memory] {
            let mut p = Interp::with_limits(limits);
            let r = p.run(src);
            if let Some(f) = p.global("Surf1").cloned() {
                let _ = p.call(&f, &[0.5, 0.5]);
            }
            drop(r);
            drop(p);
            assert_eq!(crate::meter::live(), start, "{}", &src[..src.len().min(60)]);
        }
    }
}

#[test]
fn maps_whose_kernel_outgrows_the_memory_budget_are_interpreted() {
    // 501 operations, whose slots for a block of points take 256 KB: within a budget of 256 KiB
    // the map is interpreted, to the same points.
    let terms: Vec<String> = (1..=250).map(|i| format!("K:{i} + S1")).collect();
    let src = format!("MAP:[{}]:(interval:<0, 1>:31);", terms.join(", "));
    let tight = Limits {
        memory: 256 << 10,
        ..Limits::default()
    };
    let (fast, slow) = (
        Interp::new().run(&src),
        Interp::with_limits(tight).run(&src),
    );
    assert!(
        fast.error.is_none() && slow.error.is_none(),
        "{:?}",
        slow.error
    );
    assert!(
        slow.steps > 2 * fast.steps,
        "interpreted: {} steps",
        slow.steps
    );
    assert!(fast.memory > 256 << 10 && slow.memory < 256 << 10);
    assert_eq!(pol(&fast.shown[0]), pol(&slow.shown[0]));
}

#[test]
fn calls_under_way_count_against_the_memory_budget() {
    // Each call of `f` holds a slot for each of its 5,000 locals (80 KB), used or not: a
    // recursion 60 calls deep holds 5 MB, past a budget of 2 MiB before the call limit.
    let locals: Vec<String> = (1..=5000).map(|i| format!("a{i} = {i}")).collect();
    let src = format!(
        "DEF f (n::IsNat) = IF:<C:EQ:0, K:0, f ~ C:-:1>:n WHERE {} END;\nf:60;",
        locals.join(", ")
    );
    let tight = Limits {
        memory: 2 << 20,
        ..Limits::default()
    };
    let e = Interp::with_limits(tight).run(&src).error.expect("past");
    assert_eq!((e.kind, e.span.line), (ErrorKind::Limit, 1), "{e}");
    assert!(e.message.contains("memory"), "{e}");
    assert!(Interp::new().run(&src).error.is_none());
}
