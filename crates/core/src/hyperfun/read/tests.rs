//! The reader against HyperFun's own interpreter. Every expected message, line, position and value
//! here was printed by HyperFun's C interpreter (HyperFun 1.x, `int_parse_N.c` and `int_calc.c`,
//! built as a command-line checker) on the same text at the point (0.5, 0, 0) unless stated.

// HyperFun's values are quoted as it prints them (`%.17g`), one digit past the shortest.
#![allow(clippy::excessive_precision)]

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

use super::{HfError, HfErrorKind, MAX_DEPTH, MAX_OPERATIONS, Program};
use crate::testutil::Rng;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

const P: [f64; 3] = [0.5, 0.0, 0.0];

fn run(text: &str, x: [f64; 3]) -> Result<f64, HfError> {
    Program::parse(text)?.eval(x)
}

fn value(text: &str) -> f64 {
    run(text, P).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The error of `text` at `P`: its kind, line, position and message.
fn error(text: &str) -> (HfErrorKind, u32, u32, String) {
    let e = run(text, P).expect_err(text);
    (e.kind, e.line, e.position, String::from(&*e.message))
}

fn parse_error(text: &str, line: u32, position: u32, message: &str) {
    assert_eq!(
        error(text),
        (HfErrorKind::Parse, line, position, String::from(message)),
        "{text}"
    );
}

fn runtime_error(text: &str, line: u32, position: u32, message: &str) {
    assert!(Program::parse(text).is_ok(), "{text}");
    assert_eq!(
        error(text),
        (HfErrorKind::Runtime, line, position, String::from(message)),
        "{text}"
    );
}

#[test]
fn read_refuses_a_local_named_s() {
    // The export's first bug: `s` is HyperFun's third array, so `s = …` wants `[`.
    let text = "my_model(x[3], a[1])\n{\n  s = x[1]*x[1] + x[2]*x[2];\n  my_model = 1 - s - x[3]*x[3];\n}\n";
    parse_error(text, 3, 7, "Left bracket expected");
}

#[test]
fn read_refuses_a_condition_opening_with_a_bracket() {
    let text = "my_model(x[3], a[1])\n{\n  a1 = x[1]; b1 = x[2]; c1 = 1;\n  r = -1;\n  \
                if ((a1 - b1) * (a1 - b1) <= c1) then\n    r = 1;\n  endif;\n  my_model = r;\n}\n";
    parse_error(text, 5, 17, "Right parenthes expected");
    // A bracket later in the condition is arithmetic.
    let ok = "m(x[3], a[1]) { r = 0; if 0 + (x[1] - 1) * 2 < 0 then r = 1; endif; m = r; }";
    assert_eq!(value(ok), 1.0);
    parse_error(
        "m(x[3], a[1]) { r = 0; if (x[1]) + 1 > 0 then r = 1; endif; m = r; }",
        1,
        34,
        "Reserved word \"then\" expected",
    );
}

#[test]
fn read_division_by_less_than_eps_is_an_error() {
    let text = "my_model(x[3], a[1])\n{\n  d = 1e-7;\n  my_model = 1 / d;\n}\n";
    runtime_error(text, 4, 16, "Division by zero");
    runtime_error(
        "m(x[3], a[1]) { m = 1 / 0.0000001; }",
        1,
        23,
        "Division by zero",
    );
    assert_eq!(
        value("m(x[3], a[1]) { m = 1 / 0.000001; }"),
        1.0 / 0.000_001
    );
}

#[test]
fn read_numbers_as_hyperfun_reads_them() {
    assert_eq!(
        value("m(x[3], a[1]) { m = 1e-15; }"),
        9.999_999_999_999_980_5e-6
    );
    assert_eq!(
        value("m(x[3], a[1]) { m = 1e-15 * 1e15; }"),
        10_000_000_000.000_04
    );
    parse_error("m(x[3], a[1]) { m = 05; }", 1, 21, "Expression expected");
    parse_error("m(x[3], a[1]) { m = 1e05; }", 1, 21, "Expression expected");
    parse_error(
        "m(x[3], a[1]) { m = sqrt(\"4\"); }",
        1,
        26,
        "Expression expected",
    );
    parse_error(
        "m(x[3], a[1]) {\tr =\t#; m = 1; }",
        1,
        21,
        "Expression expected",
    );
}

#[test]
fn read_refuses_reserved_names_as_variables() {
    parse_error(
        "m(x[3], a[1]) { sin = 1; m = sin; }",
        1,
        17,
        "Body name expected",
    );
    parse_error(
        "m(x[3], a[1]) { r = max; m = r; }",
        1,
        24,
        "Left parenthes expected",
    );
    parse_error(
        "m(x[3], a[1]) { hfSphere = 1; m = 1; }",
        1,
        17,
        "Body name expected",
    );
    parse_error(
        "m(x[3], a[1]) { if = 1; m = 1; }",
        1,
        20,
        "Expression expected",
    );
}

#[test]
fn read_use_before_assignment() {
    let unknown = "m(x[3], a[1]) {\n  m = q + 1; }";
    parse_error(unknown, 2, 7, "Unassigned identificator used in expression");
    // Declared in the text, but not assigned at this point.
    let untaken = "m(x[3], a[1]) { if x[1] > 5 then q = 1; endif;\n  m = q; }";
    runtime_error(untaken, 2, 7, "Not initialized variable");
    // The first assignment declares the name before its value is read.
    runtime_error(
        "m(x[3], a[1]) { r = r + 1; m = r; }",
        1,
        21,
        "Not initialized variable",
    );
}

#[test]
fn read_whole_array_assignments_take_exactly_the_size() {
    let few = "m(x[3], a[1]) { array p[3]; p = [1, -2]; m = p[1]; }";
    parse_error(few, 1, 39, "Comma expected");
    let many = "m(x[3], a[1]) { array p[2]; p = [1, -2, +3]; m = p[1]; }";
    parse_error(many, 1, 39, "Right bracket expected");
    parse_error(
        "m(x[3], a[1]) { array p[2]; p = [1, 2 * 3]; m = 1; }",
        1,
        39,
        "Right bracket expected",
    );
    parse_error(
        "m(x[3], a[1]) { array p[2]; p = [1, - -2]; m = 1; }",
        1,
        39,
        "Real number expected",
    );
    let s = "m(x[3], a[1], s[3]) { s = [1, -2, 3.5]; m = s[1] + s[2] * 10 + s[3] * 100; }";
    assert_eq!(value(s), 331.0);
}

#[test]
fn read_a_loop_that_never_ends_runs_out_of_budget() {
    let text = "m(x[3], a[1]) { i = 0; while 1 loop i = i + 1; endloop; m = i; }";
    let e = run(text, P).unwrap_err();
    assert_eq!(e.kind, HfErrorKind::Limit);
    let expected = format!("the model runs past {MAX_OPERATIONS} operations at one point");
    assert_eq!(e.message, expected);
    let empty = "m(x[3], a[1]) { while 1 loop endloop; m = 1; }";
    assert_eq!(run(empty, P).unwrap_err().kind, HfErrorKind::Limit);
    // So does an integer power of a hundred million products.
    let power = "m(x[3], a[1]) { m = 1.0000001 ^ 2000000000; }";
    assert_eq!(run(power, P).unwrap_err().kind, HfErrorKind::Limit);
}

#[test]
fn read_deep_nesting_is_a_cap_not_a_stack_overflow() {
    let deep = |open: &str, close: &str, n: usize, wrap: &dyn Fn(String) -> String| {
        wrap(format!("{}1{}", open.repeat(n), close.repeat(n)))
    };
    let expr = |e: String| format!("m(x[3], a[1]) {{ m = {e}; }}");
    let cond = |c: String| format!("m(x[3], a[1]) {{ r = 0; if {c} then r = 1; endif; m = r; }}");
    for text in [
        deep("(", ")", 100_000, &expr),
        deep("- ", "", 100_000, &expr),
        deep("sqrt(", ")", 100_000, &expr),
        deep("x[", "]", 100_000, &expr),
        deep("not ", "", 100_000, &cond),
        deep("(", ")", 100_000, &cond),
        format!(
            "m(x[3], a[1]) {{ r = 0; {}r = 1; {} m = r; }}",
            "if 1 then ".repeat(100_000),
            "endif; ".repeat(100_000)
        ),
    ] {
        let e = Program::parse(&text).unwrap_err();
        assert_eq!(e.kind, HfErrorKind::Limit, "{e}");
    }
    // Up to the cap it reads.
    let e = deep("(", ")", MAX_DEPTH - 2, &expr);
    assert_eq!(value(&e), 1.0);
    // Long chains are loops, not recursion: a hundred thousand terms.
    let chain = expr(alloc::vec!["1"; 100_000].join(" + "));
    assert_eq!(value(&chain), 100_000.0);
    let chain = expr(alloc::vec!["x[1]"; 100_000].join(" * "));
    assert_eq!(value(&chain), 0.0);
}

#[test]
fn read_random_bytes_never_panic() {
    let valid = [
        "my_model(x[3], a[1], s[2]) { array p[3], q[2]; p = [1, -2, 3]; r = hfSphere(x, p, 2); \
         i = 1; while i < 3 loop q[i] = p[i] / i; i = i + 1; endloop; if r > 0 and not q[1] = 0 \
         then s[1] = r ^ 2; else s[2] = -r; endif; my_model = r & q[2] | s[1] \\ 1; }",
        "b(x[3], a[1]) { b = hfBlock(x, x, 1, 2, 3) @ hfBlendUni(x[1], x[2], 1, 2, 3); }\n\
         my_model(x[3], a[1]) { t = hfRotate3DZ(x, 1) + hfTaperX(x, 0, 1, 2, 3); \
         my_model = b(x, a) + mod(x[1], 3) - tan(x[2]) + log(abs(x[3]) + 1) + 1e-15; }",
    ];
    let alphabet: Vec<u8> =
        b" \n\t\r()[]{};,=<>+-*/^&|\\@~\".0123456789eExas_ifthenlopdr#\0\xc3\xa9".to_vec();
    let mut rng = Rng::new(2024);
    let points = [[0.0; 3], [1.0, -2.0, 0.5], [f64::NAN, 1e300, -1e-300]];
    for round in 0..4000 {
        let text: Vec<u8> = if round % 2 == 0 {
            (0..rng.int(0, 120))
                .map(|_| alphabet[rng.int(0, alphabet.len() - 1)])
                .collect()
        } else {
            let mut t = valid[round % 4 / 2].as_bytes().to_vec();
            for _ in 0..rng.int(1, 6) {
                let i = rng.int(0, t.len() - 1);
                match rng.int(0, 3) {
                    0 => {
                        t.remove(i);
                    }
                    1 => t.insert(i, alphabet[rng.int(0, alphabet.len() - 1)]),
                    2 => t[i] = alphabet[rng.int(0, alphabet.len() - 1)],
                    _ => {
                        let j = rng.int(0, t.len() - 1);
                        t.swap(i, j);
                    }
                }
            }
            t
        };
        let text = String::from_utf8_lossy(&text);
        if let Ok(program) = Program::parse(&text) {
            let mut e = program.evaluator();
            for p in points {
                let _ = e.eval(&p, &[2.0]);
            }
        }
    }
}

#[test]
fn read_precedence_and_order_of_evaluation() {
    let m = |e: &str| value(&format!("m(x[3], a[1]) {{ m = {e}; }}"));
    assert_eq!(m("-x[1]^2"), 0.25);
    assert_eq!(m("2^3^2"), 64.0);
    assert_eq!(m("2^-1"), 0.5);
    assert_eq!(m("- -2 + ~~3"), 5.0);
    assert_eq!(m("2 & 3 - 1"), 0.394_448_724_536_010_9);
    assert_eq!(m("1 - 2 & 3"), super::library::r_and(-1.0, 3.0));
    let cond = |c: &str| {
        value(&format!(
            "m(x[3], a[1]) {{ r = 5; if {c} then r = 7; endif; m = r; }}"
        ))
    };
    assert_eq!(cond("1 or 0 and 0"), 5.0);
    assert_eq!(cond("3 < 2 < 1"), 7.0);
    assert_eq!(cond("not 0 < 0.5"), 5.0);
    assert_eq!(cond("1 = 1.0000009"), 7.0);
    // 1.000001 reads as 1 + 0.9999999999954e-6: within EPS of 1.
    assert_eq!(cond("1 = 1.000001"), 7.0);
    assert_eq!(cond("1 = 1.0000011"), 5.0);
    assert_eq!(cond("x[1]"), 7.0);
    assert_eq!(cond("(x[1] > 0) and ((x[2] < 1))"), 7.0);
    // Right operands, and last arguments, first: the shift has moved x when the sphere reads it.
    let sphere = "m(x[3], a[1]) { array c[3]; c = [0, 0, 0]; m = hfSphere(x, c, 1) + hfShift3D(x, 5, 0, 0); }";
    assert_eq!(value(sphere), -18.25);
    assert_eq!(m("x[1] + hfShift3D(x, 1, 0, 0)"), 0.5);
    assert_eq!(m("min(x[1], hfShift3D(x, 1, 0, 0))"), -0.5);
    runtime_error(
        "m(x[3], a[1]) { m = log(0) + logd(100); }",
        1,
        21,
        "Negative for log function",
    );
    runtime_error(
        "m(x[3], a[1]) { m = log(1) + logd(-1); }",
        1,
        30,
        "Negative for log function",
    );
    assert_eq!(value("m(x[3], a[1]) { r = (x[1]); m = r; }"), 0.5);
    parse_error(
        "m(x[3], a[1]) { r = (x[1] > 0); m = r; }",
        1,
        27,
        "Right parenthes expected",
    );
}

#[test]
fn read_powers_and_built_ins_with_eps() {
    let m = |e: &str| value(&format!("m(x[3], a[1]) {{ m = {e}; }}"));
    assert_eq!(m("2^2.0000009 + (-2)^3 * 10 + (-2)^(-2) * 100"), -51.0);
    assert_eq!(m("1.0000001^1000000"), 1.105_170_912_614_313_4);
    // `(int)` of 1e10 is INT_MIN on x86: no products, 1.
    assert_eq!(m("0.5^1e10 + 2^-1"), 0.5);
    assert_eq!(m("(-1)^2147483647 + 1^2147483646 * 10"), 9.0);
    assert_eq!(
        m(
            "mod(-7.5, 2) * 100 + mod(7.5, 2.4) * 10 + int(-2.75) + frac(-2.75) * 1000 + sign(-3) * 10000"
        ),
        9148.0
    );
    assert_eq!(m("mod(1e300, 7)"), -2.0);
    let err = |e: &str, pos: u32, message: &str| {
        runtime_error(&format!("m(x[3], a[1]) {{ m = {e}; }}"), 1, pos, message);
    };
    err("0^0", 22, "Zero value in negative or zero power");
    err("(-2)^2.5", 25, "Negative value for power");
    err(
        "tan(1.5707963267948966)",
        21,
        "Cannot compute tan for this argument",
    );
    err("sqrt(-0.0000001)", 21, "Negative value for square root");
    err(
        "asin(1.0000001)",
        21,
        "Argument must be in range -1.0 .. +1.0",
    );
}

#[test]
fn read_arrays_report_where_hyperfun_does() {
    // A read's index error is at the index's first operand, a write's at its first token.
    let read = "m(x[3], a[1]) { array p[2]; p[1] = 1; p[2] = 2;\n  m = p[x[1] + 3]; }";
    runtime_error(read, 2, 11, "Array index out of range");
    let write = "m(x[3], a[1]) { array p[2];\n  p[(x[1]) + 5] = 1; m = 1; }";
    runtime_error(write, 2, 5, "Array index out of range");
    let unset = "m(x[3], a[1]) { array p[2]; p[1] = 1;\n  m = p[2]; }";
    runtime_error(unset, 2, 7, "Unassigned identificator used in expression");
    let arg = "m(x[3], a[1]) { array p[3]; p[1] = 1;\n  m = hfSphere(x, p, 1); }";
    runtime_error(arg, 2, 19, "Some items of array are unassigned");
    // Infinite, NaN and past C's int: out of range (x86's INT_MIN).
    for index in [
        "1e300 * 1e300",
        "1e300 * 1e300 - 1e300 * 1e300",
        "1e10",
        "2147483648.5",
    ] {
        let text = format!("m(x[3], a[1]) {{ m = x[{index}]; }}");
        runtime_error(&text, 1, 23, "Array index out of range");
    }
    assert_eq!(value("m(x[3], a[1]) { m = x[0.5] + x[1.4999] * 10; }"), 5.5);
    // A header size is rounded, and may be 0.
    assert_eq!(value("m(x[2.5], a[0], s[0]) { m = x[3] + 1; }"), 1.0);
}

#[test]
fn read_bodies_calls_and_selection() {
    let call = "b(x[3], a[1], s[2]) { s[1] = x[1] * 2; s[2] = 7; b = x[2] + 1; }\n\
                my_model(x[3], a[1], s[2]) { v = b(x, a, s); my_model = v + s[1] * 10 + s[2] * 100; }";
    assert_eq!(value(call), 711.0);
    // B(x, a) passes the caller's s[1] and brings it back.
    let two = "b(x[3], a[1]) { s[1] = s[1] * 10 + 1; b = 2; }\n\
               my_model(x[3], a[1]) { s[1] = 4; v = b(x, a);\n  my_model = v * 1000 + s[1]; }";
    assert_eq!(value(two), 2041.0);
    // An unassigned item is reported one argument late: p's at `a`, q's at `)`.
    let late = "b(x[3], a[1]) { b = x[1]; }\n\
                my_model(x[3], a[1]) { array p[3]; p[1] = 1;\n  my_model = b(p, a); }";
    runtime_error(late, 3, 19, "Some items of array are unassigned");
    let late = "b(x[3], a[3]) { b = a[2]; }\n\
                my_model(x[3], a[1]) { array p[3], q[3]; q[1] = 1;\n  my_model = b(x, q); }";
    runtime_error(late, 3, 20, "Some items of array are unassigned");
    let sizes = "b(x[3], a[2]) { b = 1; }\nm(x[3], a[1]) { m = b(x, a); }";
    parse_error(sizes, 2, 26, "Wrong number of items in array");
    parse_error(
        "b(x[3], a[1]) { b = b(x, a); }",
        1,
        21,
        "Unassigned identificator used in expression",
    );
    parse_error(
        "b(x[3], a[1]) { b = 1; }\nb(x[3], a[1]) { b = 2; }",
        2,
        1,
        "Body name is not unique",
    );
    // A scalar named like a body hides it from its assignment on.
    let hide = "b(x[3], a[1]) { b = 3; }\n\
                my_model(x[3], a[1]) { v = b(x, a); b = 4; my_model = v * 10 + b; }";
    assert_eq!(value(hide), 34.0);
    // The first body unless one is named my_model.
    let two =
        Program::parse("first(x[3], a[1]) { first = 11; }\nSecond(x[3], a[1]) { second = 22; }")
            .unwrap();
    assert_eq!(two.body_names().collect::<Vec<_>>(), ["first", "second"]);
    assert_eq!((two.body(), two.eval(P).unwrap()), ("first", 11.0));
    let mut two = Program::parse(
        "first(x[3], a[1]) { first = 11; }\nMy_Model(x[3], a[1]) { my_model = 22; }",
    )
    .unwrap();
    assert_eq!(two.eval(P).unwrap(), 22.0);
    assert!(two.select("first"));
    assert!(!two.select("third"));
    assert_eq!((two.eval(P).unwrap(), two.dims()), (11.0, [3, 1, 1]));
    parse_error("m(x[3]) { m = 1; }", 1, 7, "Comma expected");
    parse_error(
        "m(x[3], a[1]) { if 1 then m = 1; endif; m = 2; }",
        1,
        27,
        "Reserved words \"else\" or \"endif\" expected",
    );
    parse_error(
        "m(x[3], a[1]) { i = 0; while i < 3 i = i + 1; endloop; m = i; }",
        1,
        36,
        "Reserved word \"loop\" expected",
    );
    assert_eq!(
        Program::parse("-- nothing\n").unwrap_err().kind,
        HfErrorKind::Unsupported
    );
}

#[test]
fn read_s_persists_in_an_evaluator_and_a_is_refilled() {
    let text = "m(x[3], a[2]) { if x[1] > 0 then s[1] = x[1]; endif; m = s[1] + a[2] * 100; }";
    let program = Program::parse(text).unwrap();
    let mut e = program.evaluator();
    let got: Vec<f64> = [1.0, -1.0, 5.0, -1.0]
        .iter()
        .map(|&v| e.eval(&[v], &[0.0, 1.0]).unwrap())
        .collect();
    assert_eq!(got, [101.0, 101.0, 105.0, 105.0]);
    assert_eq!(e.s(), [5.0]);
    // Program::eval starts from s = 0 every time.
    assert_eq!(
        program.eval_with([-1.0, 0.0, 0.0], &[0.0, 2.0]).unwrap(),
        200.0
    );
}

#[test]
fn read_refuses_what_it_does_not_evaluate_at_the_call() {
    let e = Program::parse("m(x[3], a[1]) { m = 1 + hfA_Wave(1, 2, 3, 4); }").unwrap_err();
    assert_eq!(
        (e.kind, e.line, e.position),
        (HfErrorKind::Unsupported, 1, 25)
    );
    assert_eq!(
        e.message,
        "hfA_Wave is a HyperFun library function this reader does not evaluate"
    );
    let e = Program::parse("b(x[3], a[1]) { b = 1; }\nm(x[3], a[1]) { m = b(1, a); }").unwrap_err();
    assert_eq!(
        (e.kind, e.line, e.position),
        (HfErrorKind::Unsupported, 2, 23)
    );
}

#[test]
fn read_takes_crlf_and_reports_as_hyperfun_does() {
    let text = "my_model(x[3], a[1])\r\n{\r\n  d = 1e-7;\r\n  my_model = 1 / d;\r\n}\r\n";
    let e = run(text, P).unwrap_err();
    assert_eq!(e.to_string(), "line 4, position 16: Division by zero");
    parse_error("m(x[3], a[1])\r{ m = 1; }", 1, 14, "Left brace expected");
}

#[test]
fn read_caps_are_typed_errors() {
    let big = format!(
        "m(x[3], a[1]) {{ array p[{}]; m = 1; }}",
        super::MAX_CELLS + 1
    );
    assert_eq!(Program::parse(&big).unwrap_err().kind, HfErrorKind::Limit);
    // An `(int)` overflow is a size below 1, as on x86.
    parse_error(
        "m(x[3], a[1]) { array p[3e9]; m = 1; }",
        1,
        25,
        "Array size must be greater zero",
    );
    let long = " ".repeat(super::MAX_SOURCE_BYTES + 1);
    assert_eq!(Program::parse(&long).unwrap_err().kind, HfErrorKind::Limit);
}

#[test]
fn read_runs_a_million_step_loop() {
    let text = "m(x[3], a[1]) { i = 0; t = 0; while i < 1000000 loop t = t + x[1] * i; i = i + 1; endloop; m = t; }";
    let program = Program::parse(text).unwrap();
    assert_eq!(program.eval(P).unwrap(), 0.5 * 499_999_500_000.0);
}
