//! The library functions through the reader against their definitions, written again here
//! independently (plain formulas, `std` math, numerical integrals for the convolutions), and a
//! handful against values printed by HyperFun's own C interpreter.

// HyperFun's values are quoted as it prints them (`%.17g`), one digit past the shortest.
#![allow(clippy::excessive_precision)]

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

use super::library::{FUNCTIONS, Imp, SENTINEL};
use super::{HfErrorKind, Program};
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

const C: [f64; 3] = [0.1, -0.2, 0.3];
const V: [f64; 3] = [-0.5, -0.4, -0.6];
const PX: [f64; 3] = [0.1, -0.3, 0.5];
const PY: [f64; 3] = [0.2, 0.4, -0.1];
const PZ: [f64; 3] = [-0.2, 0.3, 0.1];
const PA: [f64; 3] = [2.0, 3.0, 1.5];
const PB: [f64; 3] = [1.0, 0.5, 2.0];
const PV: [f64; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
const PE: [f64; 9] = [0.5, 0.5, 0.5, 1.0, 1.0, 0.0, 0.0, 1.0, 1.0];
const PS: [f64; 3] = [1.5, 2.0, 0.7];
const TV: [f64; 18] = [
    0.0, 0.0, 0.0, 1.0, 0.2, 0.0, 0.3, 1.0, 0.1, 0.0, 0.0, 0.2, 1.0, 1.0, 0.5, 0.3, 1.2, 1.0,
];
const TS: [f64; 2] = [1.3, 2.1];
const BB: [f64; 6] = [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0];

fn weights() -> [f64; 27] {
    core::array::from_fn(|i| ((i * 7 % 11) as f64 - 5.0) / 4.0)
}

/// `expr` in a model that declares the arrays above, at `x`.
fn model(expr: &str) -> Program {
    let list = |v: &[f64]| {
        v.iter()
            .map(|c| format!("{c}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let arrays = [
        ("c", &C[..]),
        ("v", &V[..]),
        ("px", &PX[..]),
        ("py", &PY[..]),
        ("pz", &PZ[..]),
        ("pa", &PA[..]),
        ("pb", &PB[..]),
        ("pv", &PV[..]),
        ("pe", &PE[..]),
        ("ps", &PS[..]),
        ("tv", &TV[..]),
        ("ts", &TS[..]),
        ("bb", &BB[..]),
        ("w", &weights()[..]),
    ];
    let mut text = String::from("my_model(x[3], a[1]) {\n  array ");
    let decls: Vec<String> = arrays
        .iter()
        .map(|(n, v)| format!("{n}[{}]", v.len()))
        .collect();
    text += &decls.join(", ");
    text += ";\n";
    for (n, v) in arrays {
        text += &format!("  {n} = [{}];\n", list(v));
    }
    text += &format!("  my_model = {expr};\n}}\n");
    Program::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Checks `expr` against `want` at random points, to a relative `tol`.
fn agrees(expr: &str, tol: f64, want: impl Fn([f64; 3]) -> f64) {
    let program = model(expr);
    let mut rng = Rng::new(expr.len() as u64);
    for _ in 0..40 {
        let p = [0; 3].map(|_| rng.range(-1.5, 1.5));
        let (got, want) = (program.eval(p).unwrap(), want(p));
        assert!(
            (got - want).abs() <= tol * want.abs().max(1.0),
            "{expr} at {p:?}: {got} against {want}"
        );
    }
}

fn d(p: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| p[i] - C[i])
}

fn sq(v: f64) -> f64 {
    v * v
}

fn inter(a: f64, b: f64) -> f64 {
    a + b - a.hypot(b)
}

#[test]
fn library_primitives_match_their_formulas() {
    let t = 1e-13;
    agrees("hfSphere(x, c, 1.2)", t, |p| {
        1.44 - d(p).iter().map(|v| v * v).sum::<f64>()
    });
    agrees("hfEllipsoid(x, c, 1.2, 0.7, 1.9)", t, |p| {
        let k = [1.2, 0.7, 1.9];
        1.0 - (0..3).map(|i| sq(d(p)[i] / k[i])).sum::<f64>()
    });
    agrees("hfBlock(x, v, 1, 0.8, 1.2)", t, |p| {
        let t = [1.0, 0.8, 1.2];
        let f = |i: usize| (p[i] - V[i]) * (V[i] + t[i] - p[i]);
        inter(inter(f(0), f(1)), f(2))
    });
    for (axis, name) in ["X", "Y", "Z"].iter().enumerate() {
        let across = |p: [f64; 3], k: [f64; 2]| {
            let others: Vec<f64> = (0..3).filter(|&i| i != axis).map(|i| d(p)[i]).collect();
            sq(others[0] / k[0]) + sq(others[1] / k[1])
        };
        agrees(&format!("hfCylinder{name}(x, c, 0.7)"), t, |p| {
            0.49 - across(p, [1.0; 2])
        });
        agrees(&format!("hfEllCyl{name}(x, c, 0.7, 1.3)"), t, |p| {
            1.0 - across(p, [0.7, 1.3])
        });
        agrees(&format!("hfCone{name}(x, c, 0.6)"), t, |p| {
            sq(d(p)[axis]) - across(p, [0.6, 0.6])
        });
        agrees(&format!("hfEllCone{name}(x, c, 0.6, 1.4)"), t, |p| {
            sq(d(p)[axis]) - across(p, [0.6, 1.4])
        });
        // R the major radius, r0 the minor one.
        agrees(&format!("hfTorus{name}(x, c, 1, 0.3)"), t, |p| {
            let ring = across(p, [1.0; 2]).sqrt();
            0.09 - sq(d(p)[axis]) - sq(ring - 1.0)
        });
    }
    agrees("hfSuperell(x, c, 1, 1.2, 0.8, 0.7, 1.6)", 1e-12, |p| {
        let (s1, s2) = (0.7, 1.6);
        let [u, v, w] = [0, 1, 2].map(|i| (d(p)[i] / [1.0, 1.2, 0.8][i]).abs());
        1.0 - (u.powf(2.0 / s2) + v.powf(2.0 / s2)).powf(s2 / s1) - w.powf(2.0 / s1)
    });
    let bump = |p: [f64; 3]| p[2] / (1.0 + sq(p[0] / 0.8) + sq(p[1] / 1.3));
    agrees("hfBlendUni(x[1], x[2], x[3], 0.8, 1.3)", t, |p| {
        p[0] + p[1] + p[0].hypot(p[1]) + bump(p)
    });
    agrees("hfBlendInt(x[1], x[2], x[3], 0.8, 1.3)", t, |p| {
        inter(p[0], p[1]) + bump(p)
    });
    agrees("hfNoiseG(x, 2.5, 0.7, 1.4)", 1e-12, |p| {
        let s = p.map(|c| (0.7 * c).sin());
        let b = 2.5 / 1.17;
        (0..3)
            .map(|i| 2.5 * s[i] + b * (0.7 * p[i] / 1.35 + 1.4 * s[(i + 2) % 3]).sin())
            .product::<f64>()
    });
}

#[test]
fn library_sums_match_their_formulas() {
    let r2 = |p: [f64; 3], i: usize| sq(p[0] - PX[i]) + sq(p[1] - PY[i]) + sq(p[2] - PZ[i]);
    agrees("hfBlobby(x, px, py, pz, pa, pb, 0.5)", 1e-13, |p| {
        (0..3)
            .map(|i| PB[i] * (-PA[i] * r2(p, i)).exp())
            .sum::<f64>()
            - 0.5
    });
    agrees("hfMetaball(x, px, py, pz, pb, pa, 0.3)", 1e-13, |p| {
        let term = |i: usize| {
            let (r, dd) = (r2(p, i).sqrt(), PA[i]);
            if r <= dd / 3.0 {
                PB[i] * (1.0 - 3.0 * sq(r / dd))
            } else if r < dd {
                1.5 * PB[i] * sq(1.0 - r / dd)
            } else {
                0.0
            }
        };
        (0..3).map(term).sum::<f64>() - 0.3
    });
    agrees("hfSoft(x, px, py, pz, pa, 0.2)", 1e-12, |p| {
        let term = |i: usize| {
            let (q, dd) = (r2(p, i), sq(PA[i]));
            if q > dd {
                return 0.0;
            }
            1.0 - 22.0 / 9.0 * q / dd + 17.0 / 9.0 * sq(q / dd) - 4.0 / 9.0 * (q / dd).powi(3)
        };
        (0..3).map(term).sum::<f64>() - 0.2
    });
    let cauchy = |s: f64, q: f64| 1.0 / sq(1.0 + s * s * q);
    let dist2 = |p: [f64; 3], q: [f64; 3]| (0..3).map(|i| sq(p[i] - q[i])).sum::<f64>();
    agrees("hfConvPoint(x, pv, ps, 0.5)", 1e-13, |p| {
        let point = |n: usize| [PV[3 * n], PV[3 * n + 1], PV[3 * n + 2]];
        (0..3)
            .map(|n| cauchy(PS[n], dist2(p, point(n))))
            .sum::<f64>()
            - 0.5
    });
    // A segment's term is ∫ 1/(1 + s²r²)² along it (Simpson's rule, 2000 panels).
    agrees("hfConvLine(x, pv, pe, ps, 0.5)", 1e-9, |p| {
        let seg = |n: usize| {
            let (b, e) = (
                [0, 1, 2].map(|i| PV[3 * n + i]),
                [0, 1, 2].map(|i| PE[3 * n + i]),
            );
            let at = |t: f64| [0, 1, 2].map(|i| b[i] + t * (e[i] - b[i]));
            let m = 2000;
            let sum: f64 = (0..=m)
                .map(|k| {
                    let w = if k == 0 || k == m {
                        1.0
                    } else if k % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * cauchy(PS[n], dist2(p, at(k as f64 / m as f64)))
                })
                .sum();
            sum / (3.0 * m as f64) * dist2(b, e).sqrt()
        };
        (0..3).map(seg).sum::<f64>() - 0.5
    });
    // A triangle's term is s³ · ∬ 1/(1 + s²r²)² over it (centroids of a 200² subdivision).
    let program = model("hfConvTriangle(x, tv, ts, 0)");
    for p in [[0.3, -0.45, 0.2], [0.5, 0.5, 1.5], [-1.0, 0.2, 0.4]] {
        let tri = |n: usize| {
            let v = |k: usize| [0, 1, 2].map(|i| TV[9 * n + 3 * k + i]);
            let (a, e1, e2) = (
                v(0),
                [0, 1, 2].map(|i| v(1)[i] - v(0)[i]),
                [0, 1, 2].map(|i| v(2)[i] - v(0)[i]),
            );
            let cross = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let m = 200;
            let mut sum = 0.0;
            for i in 0..m {
                for j in 0..m - i {
                    let mut cells = alloc::vec![(i as f64 + 1.0 / 3.0, j as f64 + 1.0 / 3.0)];
                    if i + j < m - 1 {
                        cells.push((i as f64 + 2.0 / 3.0, j as f64 + 2.0 / 3.0));
                    }
                    for (u, w) in cells {
                        let q =
                            [0, 1, 2].map(|k| a[k] + u / m as f64 * e1[k] + w / m as f64 * e2[k]);
                        sum += cauchy(TS[n], dist2(p, q));
                    }
                }
            }
            let area = 0.5 * cross.iter().map(|c| c * c).sum::<f64>().sqrt();
            TS[n].powi(3) * sum * area / (m * m) as f64
        };
        let want = tri(0) + tri(1);
        let got = program.eval(p).unwrap();
        assert!(
            (got - want).abs() < 1e-5 * want.abs(),
            "{p:?}: {got} against {want}"
        );
    }
    agrees("hfBezierVolume(x, 3, 3, 3, bb, w)", 1e-13, |p| {
        let b = |i: usize, t: f64| [sq(1.0 - t), 2.0 * t * (1.0 - t), sq(t)][i];
        let [u, v, t] = [0, 1, 2].map(|i| (p[i] + 1.0) / 2.0);
        let w = weights();
        let mut s = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    // The library's second index runs along z, its third along y.
                    s += b(i, u) * b(j, t) * b(k, v) * w[9 * i + 3 * j + k];
                }
            }
        }
        let clip = p.map(|c| (1.0 - c) * (c + 1.0));
        inter(inter(inter(clip[0], clip[1]), clip[2]), s)
    });
}

#[test]
fn library_transformations_change_their_array_in_place() {
    // Each returns 1; the value shows x after it (the right operand runs first).
    let after = |call: &str| format!("x[1] * 1000000 + x[2] * 1000 + x[3] + {call} * 0");
    let enc = |x: [f64; 3]| x[0] * 1e6 + x[1] * 1e3 + x[2];
    let turn =
        |u: f64, v: f64, th: f64| (u * th.cos() + v * th.sin(), -u * th.sin() + v * th.cos());
    let t = 1e-12;
    agrees(&after("hfShift3D(x, 1.5, 0.5, 2)"), t, |p| {
        enc([p[0] - 1.5, p[1] - 0.5, p[2] - 2.0])
    });
    agrees(&after("hfScale3D(x, 1.5, 0.5, 2)"), t, |p| {
        enc([p[0] / 1.5, p[1] / 0.5, p[2] / 2.0])
    });
    agrees(&after("hfStretch3D(x, c, 1.5, 0.5, 2)"), t, |p| {
        enc([0, 1, 2].map(|i| C[i] + (p[i] - C[i]) / [1.5, 0.5, 2.0][i]))
    });
    agrees(&after("hfRotate3DX(x, 0.7)"), t, |p| {
        let (y, z) = turn(p[1], p[2], 0.7);
        enc([p[0], y, z])
    });
    agrees(&after("hfRotate3DY(x, 0.7)"), t, |p| {
        let (z, x) = turn(p[2], p[0], 0.7);
        enc([x, p[1], z])
    });
    agrees(&after("hfRotate3DZ(x, 0.7)"), t, |p| {
        let (x, y) = turn(p[0], p[1], 0.7);
        enc([x, y, p[2]])
    });
    agrees(&after("hfTwistZ(x, -1, 2, 0.3, 1.1)"), t, |p| {
        let tau = (p[2] + 1.0) / 3.0;
        let (x, y) = turn(p[0], p[1], (1.0 - tau) * 0.3 + tau * 1.1);
        enc([x, y, p[2]])
    });
    agrees(&after("hfTaperX(x, -1, 1, 0.5, 1.5)"), t, |p| {
        let sc = 0.5 + (p[0].clamp(-1.0, 1.0) + 1.0) / 2.0;
        enc([p[0], p[1] / sc, p[2] / sc])
    });
    agrees(&after("hfTaperY(x, -1, 1, 0.5, 1.5)"), t, |p| {
        let sc = 0.5 + (p[1].clamp(-1.0, 1.0) + 1.0) / 2.0;
        enc([p[0] / sc, p[1], p[2] / sc])
    });
}

#[test]
fn library_built_ins_and_attribute_helpers_match_their_formulas() {
    let t = 1e-13;
    agrees(
        "sqrt(abs(x[1])) + exp(x[2]) + log(abs(x[3]) + 1) + logd(abs(x[1]) + 2)",
        t,
        |p| p[0].abs().sqrt() + p[1].exp() + (p[2].abs() + 1.0).ln() + (p[0].abs() + 2.0).log10(),
    );
    agrees(
        "sin(x[1]) + cos(x[2]) + atan(x[3]) + sinh(x[1]) + cosh(x[2]) + tanh(x[3])",
        t,
        |p| p[0].sin() + p[1].cos() + p[2].atan() + p[0].sinh() + p[1].cosh() + p[2].tanh(),
    );
    agrees(
        "asin(x[1] / 2) + acos(x[2] / 2) + atan2(x[1], x[2]) + tan(x[3])",
        1e-12,
        |p| (p[0] / 2.0).asin() + (p[1] / 2.0).acos() + p[0].atan2(p[1]) + p[2].tan(),
    );
    agrees(
        "max(x[1], x[2]) + min(x[2], x[3]) * 10 + ceil(x[3]) * 100 + floor(x[1]) * 1000",
        t,
        |p| p[0].max(p[1]) + p[1].min(p[2]) * 10.0 + p[2].ceil() * 100.0 + p[0].floor() * 1000.0,
    );
    agrees(
        "int(x[2] * 3) + frac(x[3] * 3) * 10 + sign(x[1]) * 100",
        t,
        |p| (p[1] * 3.0).trunc() + (p[2] * 3.0).fract() * 10.0 + 100.0,
    );
    // mod of the rounded arguments (half up), with the sign of the first.
    agrees("mod(x[1] * 10, 3)", t, |p| {
        let r = (p[0] * 10.0 + 0.5).floor();
        r % 3.0
    });
    agrees(
        "hfA_Clamp(x[1], -0.5, 0.5) + hfA_Step(x[2], 0.2) * 10",
        t,
        |p| p[0].clamp(-0.5, 0.5) + if p[1] < 0.2 { 0.0 } else { 10.0 },
    );
    // hfA_Pulse takes the upper end second, the lower third.
    agrees(
        "hfA_Pulse(x[1], 0.5, -0.5) + hfA_Floor(x[2] * 3) * 10",
        t,
        |p| f64::from(u8::from((-0.5..=0.5).contains(&p[0]))) + (p[1] * 3.0).trunc() * 10.0,
    );
    agrees("hfA_Modulo(x[1] * 5, 0.7)", 1e-12, |p| {
        (p[0] * 5.0).rem_euclid(0.7)
    });
    agrees("hfSawtooth(x[1], 7, 1.3, x[2])", 1e-12, |p| {
        let pi = core::f64::consts::PI;
        let s: f64 = (1..7)
            .map(|k| (2.0 * pi * k as f64 * p[1] * p[0]).sin() / k as f64)
            .sum();
        (0.5 - s) * 2.0 / (1.3 * pi)
    });
}

#[test]
fn library_values_from_hyperfuns_interpreter() {
    // Printed by HyperFun's own C interpreter at (0.3, −0.45, 0.2), with these arrays:
    let text = "my_model(x[3], a[1]) {
  array c[3], v[3], px[2], py[2], pz[2], pa[2], pb[2], tv[9], ts[1], bb[6], w[8];
  c = [0.1, -0.2, 0.3]; v = [-0.5, -0.4, -0.6];
  px = [0.1, -0.3]; py = [0.2, 0.4]; pz = [-0.2, 0.3]; pa = [2, 3]; pb = [1, 0.5];
  tv = [0, 0, 0, 1, 0, 0, 0, 1, 0]; ts = [1.5]; bb = [-1, -1, -1, 1, 1, 1];
  w = [0.5, -0.25, 1, 0.75, -1, 0.5, 0.25, 1];
  k = a[1];
  r = 0;
  if k = 1 then r = hfSphere(x, c, 1.2); endif;
  if k = 2 then r = hfBlock(x, v, 1, 0.8, 1.2); endif;
  if k = 3 then r = hfTorusZ(x, c, 1, 0.3); endif;
  if k = 4 then r = hfSuperell(x, c, 1, 1.2, 0.8, 0.7, 1.6); endif;
  if k = 5 then r = hfBlobby(x, px, py, pz, pa, pb, 0.5); endif;
  if k = 6 then r = hfConvTriangle(x, tv, ts, 0.1); endif;
  if k = 7 then r = hfBezierVolume(x, 2, 2, 2, bb, w); endif;
  if k = 8 then r = hfConvLine(x, tv, c, ts, 0.2); endif;
  if k = 9 then t = hfTwistZ(x, -1, 2, 0.3, 1.1); r = x[1] * 1000 + x[2]; endif;
  if k = 10 then r = hfMetaball(x, px, py, pz, pb, pa, 0.3); endif;
  my_model = r;
}";
    let hyperfun = [
        1.327_499_999_999_999_9,
        -0.051_635_478_988_551_475,
        -0.382_187_576_256_715_07,
        0.945_292_452_302_051_17,
        -0.193_197_869_301_455_66,
        0.192_852_585_886_794_96,
        0.179_711_252_984_182_5,
        -0.016_368_925_597_724_515,
        -17.842_841_096_686_46,
        0.568_385_504_803_032_4,
    ];
    let program = Program::parse(text).unwrap();
    for (k, want) in hyperfun.iter().enumerate() {
        let got = program
            .eval_with([0.3, -0.45, 0.2], &[k as f64 + 1.0])
            .unwrap();
        // The same doubles where only arithmetic and √ are involved; `libm`'s pow, exp, atan,
        // sin and cos may differ from the C library's in the last place.
        assert!(
            (got - want).abs() <= 4e-16 * want.abs(),
            "{k}: {got} against {want}"
        );
    }
    let exact = [0, 1, 2, 9];
    for k in exact {
        assert_eq!(
            program
                .eval_with([0.3, -0.45, 0.2], &[k as f64 + 1.0])
                .unwrap(),
            hyperfun[k]
        );
    }
}

#[test]
fn library_sentinels_and_undefined_cases() {
    let two = |e: &str| {
        Program::parse(&format!(
            "m(x[2], a[1]) {{ array c[3]; c = [0, 0, 0]; m = {e}; }}"
        ))
    };
    for e in [
        "hfSphere(x, c, 1)",
        "hfTorusX(x, c, 1, 2)",
        "hfConvPoint(x, c, c, 1)",
        "hfNoiseG(x, 1, 1, 1)",
    ] {
        assert_eq!(
            two(e).unwrap().eval([1.0, 2.0, 0.0]).unwrap(),
            SENTINEL,
            "{e}"
        );
    }
    let m = |e: &str| model(e).eval([0.1, 0.2, 0.3]).unwrap();
    assert_eq!(m("hfEllipsoid(x, c, 1, 0.0000001, 1)"), SENTINEL);
    assert_eq!(m("hfBlock(x, c, 1, -1, 1)"), SENTINEL);
    // a1 = 0 in a blend is no error: the bump is 0 (or NaN).
    assert_eq!(m("hfBlendUni(1, 2, 1, 0, 1)"), 3.0 + 5f64.sqrt());
    let undefined = |text: &str, line: u32, position: u32| {
        let e = Program::parse(text)
            .and_then(|p| p.eval([0.0; 3]))
            .unwrap_err();
        assert_eq!(
            (e.kind, e.line, e.position),
            (HfErrorKind::Unsupported, line, position),
            "{e}"
        );
    };
    // Short arrays, zero-size arrays, at the argument.
    undefined(
        "m(x[3], a[1]) { array c[2]; c = [0, 0]; m = hfSphere(x, c, 1); }",
        1,
        57,
    );
    undefined(
        "m(x[3], a[1]) { array b[3], s2[2]; m = hfConvLine(x, b, b, s2, 1); }",
        1,
        54,
    );
    undefined("m(x[3], a[0]) { m = hfShift3D(a, 1, 1, 1); }", 1, 31);
    undefined("m(x[3], a[1]) { m = hfRotate3DX(a, 1); }", 1, 33);
    // A zero-length segment (HyperFun's process stops), weights too few, degrees past 20.
    undefined(
        "m(x[3], a[1]) { array b[3], t[1]; b = [1, 1, 1]; t = [1]; m = hfConvLine(x, b, b, t, 1); }",
        1,
        63,
    );
    let bez = |l: u32, n: usize| {
        format!(
            "m(x[3], a[1]) {{ array bb[6], w[{n}]; bb = [-1, -1, -1, 1, 1, 1]; w = [{}]; m = hfBezierVolume(x, {l}, {l}, {l}, bb, w); }}",
            alloc::vec!["1"; n].join(", ")
        )
    };
    for text in [bez(3, 26), bez(22, 4)] {
        let at = text.find("hfBezierVolume").unwrap() as u32 + 1;
        undefined(&text, 1, at);
    }
    assert!(
        (Program::parse(&bez(3, 27)).unwrap().eval([0.0; 3]).unwrap()
            - inter(inter(inter(1.0, 1.0), 1.0), 1.0))
        .abs()
            < 1e-15
    );
}

#[test]
fn library_table_is_hyperfuns() {
    assert_eq!(FUNCTIONS.len(), 108);
    for (i, f) in FUNCTIONS.iter().enumerate() {
        assert!(
            FUNCTIONS[..i]
                .iter()
                .all(|g| !g.name.eq_ignore_ascii_case(f.name))
        );
        let text = format!("m(x[3], a[1]) {{ m = {}(x); }}", f.name.to_uppercase());
        let e = Program::parse(&text).unwrap_err();
        match f.imp {
            Imp::Unsupported => {
                assert_eq!(e.kind, HfErrorKind::Unsupported);
                let want = format!(
                    "{} is a HyperFun library function this reader does not evaluate",
                    f.name
                );
                assert_eq!(e.message, want);
            }
            // A real first parameter takes `x` as a name without `[`; an array one goes on.
            _ => assert_eq!(e.kind, HfErrorKind::Parse, "{}: {e}", f.name),
        }
    }
}
