//! The prelude: the paper's toolbox (Scripts 3.1 to 3.3, 4.2, 4.3 and 4.5), defined before every
//! script, so that `DEF c = Bezier:S1:<<0,0,0>,<1,1,0>>; MAP:c:(Domain:8);` runs alone.
//!
//! A script's own `DEF` of a name wins, so the paper's scripts, which define these names, run
//! verbatim to the same results. The prelude's definitions see one another and the built-ins,
//! never a script's: a script that defines its own `Choose` or `fun` leaves `Bezier` and
//! `CubicHermite` as they are.
//!
//! The prelude is parsed once per thread and evaluated once per [`Interp`](crate::Interp), before
//! the limits of a run apply: its steps are not a script's. Its spans lie at lines from
//! [`PRELUDE_LINE`], so that an error inside one of its definitions is reported at the script's
//! call, never at a line of the prelude.

use std::rc::Rc;

use crate::Span;
use crate::parse::{Stmt, parse_from};

/// The text (`scripts/prelude.psm`).
const TEXT: &str = include_str!("../scripts/prelude.psm");

/// The names the prelude defines, in its order.
pub const PRELUDE_NAMES: &[&str] = &[
    "SQR",
    "interval2D",
    "vectsum",
    "scalarvectprod",
    "REV",
    "Pred",
    "Fact",
    "Choose",
    "Bernstein",
    "BernsteinBasis",
    "Bezier",
    "fun",
    "HermiteBasis",
    "CubicHermite",
];

/// The prelude's text: the paper's toolbox, each block under a comment naming its script, with
/// the two lines that the printed paper lost mended (Script 4.2's `Fact` applied to `n`, and its
/// `Bernstein`'s `*` before `~`).
pub fn prelude() -> &'static str {
    TEXT
}

/// The line at which the prelude's spans begin: far past any script's (a script has at most
/// [`Limits::source`](crate::Limits::source) bytes).
pub(crate) const PRELUDE_LINE: u32 = 1 << 30;

/// Whether a span lies in the prelude.
pub(crate) fn in_prelude(span: Span) -> bool {
    span.line >= PRELUDE_LINE
}

thread_local! {
    static STATEMENTS: Rc<Vec<Stmt>> = Rc::new(
        parse_from(TEXT, PRELUDE_LINE, &mut Vec::new()).expect("the prelude parses"),
    );
}

/// The prelude's statements, parsed once per thread.
pub(crate) fn statements() -> Rc<Vec<Stmt>> {
    STATEMENTS.with(Rc::clone)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scripts::{self, EXAMPLES};
    use crate::{ErrorKind, Interp, Limits, Value};

    fn values(src: &str) -> Vec<Value> {
        let r = Interp::new().run(src);
        if let Some(e) = r.error {
            panic!("{e}\nin:\n{src}");
        }
        r.shown.into_iter().map(|s| s.value).collect()
    }

    fn binomial(n: usize, k: usize) -> f64 {
        (0..k).fold(1.0, |c, j| c * (n - j) as f64 / (j + 1) as f64)
    }

    #[test]
    fn prelude_parses_to_its_names_without_warnings() {
        let mut warnings = Vec::new();
        let stmts = parse_from(TEXT, PRELUDE_LINE, &mut warnings).expect("parses");
        assert!(warnings.is_empty(), "{warnings:?}");
        let names: Vec<&str> = stmts
            .iter()
            .map(|s| match s {
                Stmt::Def(d) => d.name(),
                Stmt::Expr(_) => panic!("the prelude only defines"),
            })
            .collect();
        assert_eq!(names, PRELUDE_NAMES);
    }

    #[test]
    fn prelude_bezier_is_the_bernstein_sum() {
        // Only the prelude: no DEF of the toolbox.
        let points = [
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [3.0, -1.0, 2.0],
            [4.0, 0.5, 1.0],
        ];
        let list: Vec<String> = points
            .iter()
            .map(|p| format!("<{},{},{}>", p[0], p[1], p[2]))
            .collect();
        let src = format!("DEF c = Bezier:S1:<{}>;\nMAP:c:(Domain:8);", list.join(","));
        let v = values(&src);
        let c = v[0].as_pol().expect("a complex");
        assert_eq!((c.dim, c.point_count(), c.cell_count()), (3, 9, 8));
        let n = points.len() - 1;
        for k in 0..=8 {
            let u = k as f64 / 8.0;
            // Σ C(n,i) uⁱ(1−u)ⁿ⁻ⁱ Pᵢ
            let want: Vec<f64> = (0..3)
                .map(|d| {
                    (0..=n)
                        .map(|i| {
                            binomial(n, i)
                                * u.powi(i as i32)
                                * (1.0 - u).powi((n - i) as i32)
                                * points[i][d]
                        })
                        .sum()
                })
                .collect();
            let got = c.point(k);
            assert!(
                got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-12),
                "{got:?} ≠ {want:?} at {u}"
            );
        }
        // The brief's two-point line runs alone too.
        let v = values("DEF c = Bezier:S1:<<0,0,0>,<1,1,0>>; MAP:c:(Domain:8);");
        let c = v[0].as_pol().expect("a complex");
        assert_eq!(c.point(4), &[0.5, 0.5, 0.0]);
    }

    #[test]
    fn prelude_cubic_hermite_is_the_hermite_sum() {
        let v = values("MAP:(CubicHermite:S1:<<1,0>,<0,1>,<0,3>,<-3,0>>):(Domain:4);");
        let c = v[0].as_pol().expect("a complex");
        let (p1, p2, t1, t2) = ([1.0, 0.0], [0.0, 1.0], [0.0, 3.0], [-3.0, 0.0]);
        for k in 0..=4 {
            let u = k as f64 / 4.0;
            let h = [
                2.0 * u * u * u - 3.0 * u * u + 1.0,
                3.0 * u * u - 2.0 * u * u * u,
                u * u * u - 2.0 * u * u + u,
                u * u * u - u * u,
            ];
            let want: Vec<f64> = (0..2)
                .map(|d| h[0] * p1[d] + h[1] * p2[d] + h[2] * t1[d] + h[3] * t2[d])
                .collect();
            let got = c.point(k);
            assert!(
                got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-12),
                "{got:?} ≠ {want:?} at {u}"
            );
        }
    }

    #[test]
    fn prelude_small_functions_compute() {
        let v = values(
            "Fact:5; Fact:0; Choose:<5, 2>; Pred:7; SQR:3; REV:<0, 1>:0.25; \
             Bernstein:S1:3:1:<0.5>; vectsum:<<1, 2>, <3, 4>>; scalarvectprod:<2, <1, 2>>; \
             LEN:(BernsteinBasis:S1:4); LEN:(HermiteBasis:S1); interval2D:<0, 0, 1, 1>:<2, 3>;",
        );
        let s: Vec<String> = v.iter().map(ToString::to_string).collect();
        assert_eq!(
            s[..11],
            [
                "120", "1", "10", "6", "9", "0.75", "0.375", "<4, 6>", "<2, 4>", "5", "4"
            ]
        );
        let grid = v[11].as_pol().expect("a complex");
        assert_eq!(grid.point_count(), 12);
    }

    #[test]
    fn prelude_fact_gives_120_where_the_printed_fact_gives_a_function() {
        assert_eq!(values("Fact:5;")[0].as_num(), Some(120.0));
        // Script 4.2 as printed defines Fact without applying its IF to n: the script's DEF
        // wins, and its Fact:5 is a function, whose value at anything is 5! (noted in scripts.rs).
        let mut p = Interp::new();
        assert!(p.run(scripts::S4_2.text).error.is_none());
        let r = p.run("Fact:5; Fact:5:5;");
        assert!(matches!(r.shown[0].value, Value::Fun(_)));
        assert_eq!(r.shown[1].value.as_num(), Some(120.0));
    }

    #[test]
    fn prelude_yields_to_a_scripts_def() {
        let v = values(
            "DEF Fact (n::IsNat) = 7;\nFact:5;\nDEF bezier = 3;\nBezier;\n\
             DEF Choose (n,k::IsNat) = 0;\nChoose:<4, 2>;\nBernstein:S1:2:1:<0.5>;\n\
             DEF fun = 1;\nS1:(CubicHermite:S1:<<1>,<2>,<0>,<0>>):<1>;",
        );
        let s: Vec<String> = v.iter().map(ToString::to_string).collect();
        // The script's Fact, its bezier (names match in any case), its Choose; the prelude's
        // Bernstein and CubicHermite keep the prelude's Choose and fun.
        assert_eq!(s, ["7", "3", "0", "0.5", "2"]);
    }

    #[test]
    fn prelude_errors_point_at_the_scripts_call() {
        let cases: &[(&str, ErrorKind, u32, u32, &str)] = &[
            // A bad argument that passes the predicates fails inside Bezier: at the call.
            (
                "\n\nDEF c = Bezier:S1:<1, 2>;",
                ErrorKind::Type,
                3,
                9,
                "Bezier",
            ),
            // A predicate fails: at the call, as for a script's own DEF.
            (
                "SQR:2;\n  Fact:(-1);",
                ErrorKind::Type,
                2,
                3,
                "does not satisfy",
            ),
            // The script's own lines keep their places.
            (
                "DEF a = Bezier:S1:<<0>, <1>>;\nDEF b = <1, 2;",
                ErrorKind::Syntax,
                2,
                14,
                "closing",
            ),
            (
                "Choose:<2, 1>;\nMAP:(CONS:alhpa):(Domain:4);",
                ErrorKind::Name,
                2,
                11,
                "alhpa",
            ),
            (
                "DEF Bezir = 1;\nBezierr;",
                ErrorKind::Name,
                2,
                1,
                "did you mean `Bezier`",
            ),
        ];
        for &(src, kind, line, col, words) in cases {
            let e = Interp::new().run(src).error.expect("an error");
            assert_eq!(
                (e.kind, e.span.line, e.span.col),
                (kind, line, col),
                "{src:?} gave {e}"
            );
            assert!(e.message.contains(words), "{src:?} gave {e}");
        }
    }

    #[test]
    fn prelude_leaves_the_paper_examples_as_they_were() {
        // Every example, and the Bézier grid after Fig. 4, with the prelude and without: the same
        // values, warnings, errors and steps.
        let mut sources: Vec<String> = EXAMPLES.iter().map(|e| e.source()).collect();
        sources.push(
            [
                scripts::S4_2,
                scripts::S4_3,
                scripts::S4_5,
                scripts::S4_8,
                scripts::S4_7_BEZIER_GRID,
            ]
            .map(|s| s.text)
            .join("\n"),
        );
        for src in &sources {
            let with = Interp::new().run(src);
            let without = Interp::without_prelude(Limits::default()).run(src);
            assert!(with.error.is_none(), "{:?}", with.error);
            assert_eq!(format!("{:?}", with.shown), format!("{:?}", without.shown));
            assert_eq!(with.warnings, without.warnings);
            assert_eq!(with.steps, without.steps);
        }
    }

    #[test]
    fn prelude_steps_are_not_the_scripts() {
        // A run's steps start from 0 and count only what the script does.
        let r = Interp::new().run("1;");
        assert!(r.steps < 5, "{}", r.steps);
        let tight = Limits {
            steps: 3,
            ..Limits::default()
        };
        assert!(Interp::with_limits(tight).run("1;").error.is_none());
    }
}
