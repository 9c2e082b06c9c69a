//! Booleans as chain algebra: identities at sample points, and complements, which are unbounded.

use alloc::vec;

use glam::DVec3;

use crate::esc::bool::{Expr, Op};
use crate::esc::chain::{EscSolid, Stats};
use crate::esc::examples::Example;
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

#[test]
fn boolean_identities_hold_at_sample_points() {
    let a = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
    let mut moved = Example::Torus.mesh();
    for p in &mut moved.positions {
        *p += DVec3::new(0.6, 0.1, 0.05);
    }
    let b = EscSolid::new(&moved).expect("valid");
    let solids = [a, b];
    let mut stats = Stats::default();
    let mut rng = Rng::new(1);
    let s = |i| Expr::Solid(i);
    let not = Expr::complement;
    let op = Expr::binary;
    use Op::{Difference as Minus, Intersection as And, Union as Or};
    for _ in 0..300 {
        let q = DVec3::new(
            rng.range(-1.6, 2.0),
            rng.range(-1.6, 1.6),
            rng.range(-1.2, 1.2),
        );
        let values = [
            solids[0].value(q, &mut stats),
            solids[1].value(q, &mut stats),
        ];
        let mut f = |i: usize| values[i];
        let v = |e: &Expr, f: &mut dyn FnMut(usize) -> i32| e.value(&mut |i| f(i));
        assert_eq!(v(&op(Or, s(0), s(0)), &mut f), values[0], "A ∪ A = A");
        assert_eq!(v(&op(And, s(0), s(0)), &mut f), values[0], "A ∩ A = A");
        assert_eq!(v(&op(And, s(0), not(s(0))), &mut f), 0, "A ∩ Aᶜ = ∅");
        assert_eq!(
            v(&op(Or, s(0), not(s(0))), &mut f),
            1,
            "A ∪ Aᶜ = everything"
        );
        assert_eq!(
            v(&not(op(Or, s(0), s(1))), &mut f),
            v(&op(And, not(s(0)), not(s(1))), &mut f),
            "De Morgan"
        );
        assert_eq!(
            v(&not(op(And, s(0), s(1))), &mut f),
            v(&op(Or, not(s(0)), not(s(1))), &mut f),
            "De Morgan"
        );
        assert_eq!(
            v(&op(Minus, s(0), s(1)), &mut f),
            v(&op(And, s(0), not(s(1))), &mut f),
            "A − B = A ∩ Bᶜ"
        );
        for e in [
            op(Or, s(0), s(1)),
            op(And, s(0), s(1)),
            op(Minus, s(0), s(1)),
        ] {
            let r = v(&e, &mut f);
            assert!(r == 0 || r == 1, "normal chains stay normal");
        }
    }
}

#[test]
fn complements_and_unions_with_them_are_unbounded() {
    let sphere = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
    let torus = EscSolid::new(&Example::Torus.mesh()).expect("valid");
    let s = |i| Expr::Solid(i);
    let not = Expr::complement;
    let op = Expr::binary;
    let far = [
        DVec3::new(100.0, 0.0, 0.0),
        DVec3::new(-3.0, 40.0, 7.0),
        DVec3::splat(-1e6),
    ];
    let mut stats = Stats::default();
    for (expr, bounded) in [
        (s(0), true),
        (not(s(0)), false),
        (not(not(s(0))), true),
        (op(Op::Union, s(0), not(s(1))), false),
        (op(Op::Intersection, s(0), not(s(1))), true),
        (op(Op::Difference, s(0), s(1)), true),
        (op(Op::Difference, not(s(0)), s(1)), false),
        (not(op(Op::Intersection, s(0), s(1))), false),
        (not(op(Op::Union, not(s(0)), s(1))), true),
    ] {
        let boolean = crate::esc::Boolean {
            solids: vec![sphere.clone(), torus.clone()],
            expr: expr.clone(),
        };
        assert_eq!(boolean.is_bounded(), bounded, "{expr:?}");
        // Far from both solids, the result holds every point or none.
        for q in far {
            assert_eq!(
                boolean.value(q, &mut stats),
                i32::from(!bounded),
                "{expr:?} {q}"
            );
        }
    }
}
