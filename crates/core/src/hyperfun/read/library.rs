//! HyperFun's function table (every name it reserves) and the functions this reader evaluates:
//! the built-ins and the library's `hf*` primitives and transformations, each written from the
//! library's definition with its operations in the library's order, so that the results are the
//! same doubles HyperFun computes (to the last bit where the C math library and `libm` agree).
//!
//! Arguments come in source order here (HyperFun's C code receives them reversed).

use alloc::format;
use alloc::string::String;

use super::run::{EPS, c_int};

/// A parameter's kind in HyperFun's table: a real expression or an array name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Param {
    /// Any expression.
    R,
    /// `x`, `a`, `s` or a declared array, passed whole, by reference.
    A,
}

/// What this reader does with a function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Imp {
    /// A built-in of one real argument.
    F1(F1),
    /// A built-in of two real arguments.
    F2(F2),
    /// A library function.
    Lib(Lib),
    /// Reserved by HyperFun, refused here.
    Unsupported,
}

/// An entry of HyperFun's function table.
#[derive(Debug)]
pub(crate) struct Function {
    /// HyperFun's spelling (names match case-insensitively).
    pub(crate) name: &'static str,
    /// The parameters' kinds, `R` or `A`, in order.
    pub(crate) params: &'static str,
    pub(crate) imp: Imp,
}

impl Function {
    pub(crate) fn param(&self, i: usize) -> Param {
        if self.params.as_bytes()[i] == b'A' {
            Param::A
        } else {
            Param::R
        }
    }
}

/// Built-ins of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub(crate) enum F1 {
    Sqrt,
    Exp,
    Log,
    Logd,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Abs,
    Sinh,
    Cosh,
    Tanh,
    Sign,
    Ceil,
    Floor,
    Int,
    Frac,
}

/// Built-ins of two arguments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub(crate) enum F2 {
    Mod,
    Max,
    Min,
    Atan2,
}

/// The library functions this reader evaluates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub(crate) enum Lib {
    Sphere,
    Ellipsoid,
    Block,
    CylinderX,
    CylinderY,
    CylinderZ,
    EllCylX,
    EllCylY,
    EllCylZ,
    TorusX,
    TorusY,
    TorusZ,
    ConeX,
    ConeY,
    ConeZ,
    EllConeX,
    EllConeY,
    EllConeZ,
    Superell,
    BlendUni,
    BlendInt,
    Blobby,
    Metaball,
    Soft,
    ConvPoint,
    ConvLine,
    ConvTriangle,
    BezierVolume,
    NoiseG,
    Scale3D,
    Shift3D,
    Rotate3DX,
    Rotate3DY,
    Rotate3DZ,
    TwistX,
    TwistY,
    TwistZ,
    TaperX,
    TaperY,
    TaperZ,
    Stretch3D,
    Clamp,
    Floor,
    Pulse,
    Step,
    Modulo,
    Sawtooth,
}

const fn f(name: &'static str, params: &'static str, imp: Imp) -> Function {
    Function { name, params, imp }
}
const fn no(name: &'static str, params: &'static str) -> Function {
    f(name, params, Imp::Unsupported)
}

/// HyperFun's function table (`functions_info` of its `int_global.c`, as the spec lists it):
/// 108 names, all reserved, in its order.
#[rustfmt::skip]
pub(crate) static FUNCTIONS: [Function; 108] = {
    use Imp::{F1 as B1, F2 as B2, Lib as L};
    [
        f("sqrt", "R", B1(F1::Sqrt)), f("exp", "R", B1(F1::Exp)), f("log", "R", B1(F1::Log)),
        f("logd", "R", B1(F1::Logd)), f("sin", "R", B1(F1::Sin)), f("cos", "R", B1(F1::Cos)),
        f("tan", "R", B1(F1::Tan)), f("asin", "R", B1(F1::Asin)), f("acos", "R", B1(F1::Acos)),
        f("atan", "R", B1(F1::Atan)), f("abs", "R", B1(F1::Abs)), f("sinh", "R", B1(F1::Sinh)),
        f("cosh", "R", B1(F1::Cosh)), f("tanh", "R", B1(F1::Tanh)), f("sign", "R", B1(F1::Sign)),
        f("mod", "RR", B2(F2::Mod)), f("max", "RR", B2(F2::Max)), f("min", "RR", B2(F2::Min)),
        f("atan2", "RR", B2(F2::Atan2)), f("ceil", "R", B1(F1::Ceil)),
        f("floor", "R", B1(F1::Floor)), f("int", "R", B1(F1::Int)), f("frac", "R", B1(F1::Frac)),
        f("hfSphere", "AAR", L(Lib::Sphere)), f("hfEllipsoid", "AARRR", L(Lib::Ellipsoid)),
        f("hfTorusZ", "AARR", L(Lib::TorusZ)), f("hfTorusX", "AARR", L(Lib::TorusX)),
        f("hfTorusY", "AARR", L(Lib::TorusY)), f("hfEllCylX", "AARR", L(Lib::EllCylX)),
        f("hfEllCylY", "AARR", L(Lib::EllCylY)), f("hfEllCylZ", "AARR", L(Lib::EllCylZ)),
        f("hfCylinderX", "AAR", L(Lib::CylinderX)), f("hfCylinderY", "AAR", L(Lib::CylinderY)),
        f("hfCylinderZ", "AAR", L(Lib::CylinderZ)), f("hfBlock", "AARRR", L(Lib::Block)),
        f("hfBlobby", "AAAAAAR", L(Lib::Blobby)), f("hfMetaball", "AAAAAAR", L(Lib::Metaball)),
        f("hfSoft", "AAAAAR", L(Lib::Soft)), f("hfScale3D", "ARRR", L(Lib::Scale3D)),
        f("hfShift3D", "ARRR", L(Lib::Shift3D)), f("hfRotate3DZ", "AR", L(Lib::Rotate3DZ)),
        f("hfRotate3DY", "AR", L(Lib::Rotate3DY)), f("hfRotate3DX", "AR", L(Lib::Rotate3DX)),
        f("hfBlendUni", "RRRRR", L(Lib::BlendUni)), f("hfBlendInt", "RRRRR", L(Lib::BlendInt)),
        f("hfTwistZ", "ARRRR", L(Lib::TwistZ)), f("hfTwistY", "ARRRR", L(Lib::TwistY)),
        f("hfTwistX", "ARRRR", L(Lib::TwistX)), f("hfStretch3D", "AARRR", L(Lib::Stretch3D)),
        f("hfTaperZ", "ARRRR", L(Lib::TaperZ)), f("hfTaperY", "ARRRR", L(Lib::TaperY)),
        f("hfTaperX", "ARRRR", L(Lib::TaperX)), f("hfConvPoint", "AAAR", L(Lib::ConvPoint)),
        f("hfConvLine", "AAAAR", L(Lib::ConvLine)), no("hfConvArc", "AAAAAAAR"),
        f("hfConvTriangle", "AAAR", L(Lib::ConvTriangle)),
        f("hfBezierVolume", "ARRRAA", L(Lib::BezierVolume)), no("hfConvLineR", "AAAR"),
        no("hfConvCurve", "AAAR"), no("hfConvMesh", "AAAAR"), f("hfNoiseG", "ARRR", L(Lib::NoiseG)),
        f("hfSuperell", "AARRRRR", L(Lib::Superell)), f("hfConeX", "AAR", L(Lib::ConeX)),
        f("hfConeY", "AAR", L(Lib::ConeY)), f("hfConeZ", "AAR", L(Lib::ConeZ)),
        f("hfEllConeX", "AARR", L(Lib::EllConeX)), f("hfEllConeY", "AARR", L(Lib::EllConeY)),
        f("hfEllConeZ", "AARR", L(Lib::EllConeZ)), no("hfSpaceMapCubic", "AAAA"),
        no("hfSpaceMapExp", "AAAA"), no("hfR", "AR"), no("hfA_Wave", "RRRR"),
        no("hfA_CheckerBoard", "AAAAAA"), no("hfA_Union", "RRAAAR"), no("hfA_Crackles", "AARAA"),
        no("hfA_Circles", "AAAA"), no("hfA_NoiseG", "ARR"), no("hfA_NoiseP", "A"),
        no("hfA_Turbulence", "AR"), no("hfA_SetColor", "RARRR"), no("hfA_SetAttributes", "RAA"),
        no("hfA_Lerp", "AAARRR"), no("hfA_Cerp", "AAARRR"), f("hfA_Clamp", "RRR", L(Lib::Clamp)),
        f("hfA_Floor", "R", L(Lib::Floor)), f("hfA_Pulse", "RRR", L(Lib::Pulse)),
        no("hfA_LookUpTable", "RAAA"), no("hfA_SmoothLookUpTable", "RAAA"),
        f("hfA_Step", "RR", L(Lib::Step)), no("hfA_SmoothStep", "RRRRRR"),
        f("hfA_Modulo", "RR", L(Lib::Modulo)), no("hfA_Spline", "AARRR"),
        no("hfA_RGBToHSV", "AA"), no("hfA_HSVToRGB", "AA"), no("hfDConeX", "AAR"),
        no("hfDConeY", "AAR"), no("hfDConeZ", "AAR"), no("hfDCylinder", "AAAR"),
        no("hfDEllipsoid", "AARRR"), no("hfDTorusX", "AARR"), no("hfDTorusY", "AARR"),
        no("hfDTorusZ", "AARR"), no("hfDUni", "RRRR"), no("hfDInt", "RRRR"), no("hfDSub", "RRRR"),
        no("hfDBlendUni", "RRR"), no("hfDBlendInt", "RRR"), f("hfSawtooth", "RRRR", L(Lib::Sawtooth)),
    ]
};

/// What the library's primitives return when the point array does not have 3 items (or a
/// parameter is degenerate): HyperFun's `-1111111111111.0`.
pub(crate) const SENTINEL: f64 = -1_111_111_111_111.0;

/// HyperFun's `ALPHA` (a constant 0): kept in the R-function formulas, where `0·∞` makes NaN.
pub(crate) const ALPHA: f64 = 0.0;

/// An array argument: its first cell and its length.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Arr {
    pub(crate) base: u32,
    pub(crate) len: u32,
}

/// Why a library call stops.
#[derive(Debug)]
pub(crate) enum LibStop {
    /// The work budget ran out inside the call.
    Budget,
    /// Something HyperFun does not define (our message).
    Undefined(String),
}

/// The array sizes a call to `lib` needs, checked when it is parsed (all sizes are known then):
/// the index of the array argument (among the array arguments, in source order) and the items it
/// must have, or `None`. HyperFun reads past the end of a shorter array; this reader refuses it.
pub(crate) fn too_short(lib: Lib, sizes: &[u32]) -> Option<(usize, u32)> {
    use Lib::*;
    let need = |i: usize, n: u32| (sizes[i] < n).then_some((i, n));
    let three = sizes.first() == Some(&3);
    match lib {
        Sphere | Ellipsoid | Block | CylinderX | CylinderY | CylinderZ | EllCylX | EllCylY
        | EllCylZ | TorusX | TorusY | TorusZ | ConeX | ConeY | ConeZ | EllConeX | EllConeY
        | EllConeZ | Superell => three.then(|| need(1, 3)).flatten(),
        Blobby | Metaball | Soft => {
            let n = sizes[1];
            need(0, 3).or_else(|| (2..sizes.len()).find_map(|i| need(i, n)))
        }
        ConvPoint | ConvTriangle => {
            let per = if lib == ConvPoint { 3 } else { 9 };
            three.then(|| need(1, per * sizes[2])).flatten()
        }
        ConvLine => three
            .then(|| need(1, 3 * sizes[3]).or_else(|| need(2, 3 * sizes[3])))
            .flatten(),
        BezierVolume => three.then(|| need(1, 6)).flatten(),
        Scale3D | Shift3D | Rotate3DX | Rotate3DY | Rotate3DZ | TwistX | TwistY | TwistZ
        | TaperX | TaperY | TaperZ => need(0, 3),
        Stretch3D => need(0, 3).or_else(|| need(1, 3)),
        NoiseG | BlendUni | BlendInt | Clamp | Floor | Pulse | Step | Modulo | Sawtooth => None,
    }
}

/// `x²`, the library's `SQ`.
fn sq(x: f64) -> f64 {
    x * x
}

fn sqrt(x: f64) -> f64 {
    crate::math::sqrt(x)
}

/// The R-function intersection with HyperFun's `ALPHA`: `(x + y − √|x² + y² − 2αxy|)/(1 + α)`.
pub(crate) fn r_and(x: f64, y: f64) -> f64 {
    (1.0 / (1.0 + ALPHA)) * (x + y - sqrt((x * x + y * y - 2.0 * ALPHA * y * x).abs()))
}

/// The R-function union: `(x + y + √|x² + y² − 2αxy|)/(1 + α)`.
pub(crate) fn r_or(x: f64, y: f64) -> f64 {
    (1.0 / (1.0 + ALPHA)) * (x + y + sqrt((x * x + y * y - 2.0 * ALPHA * y * x).abs()))
}

/// Calls `lib` with its real arguments `r` and array arguments `arrs` (each in source order) on
/// the frame's `cells` (transformations write their array in place), charging loops to `budget`.
pub(crate) fn call(
    lib: Lib,
    r: &[f64],
    arrs: &[Arr],
    cells: &mut [f64],
    budget: &mut u64,
) -> Result<f64, LibStop> {
    use Lib::*;
    let at = |a: Arr, i: usize| a.base as usize + i;
    let get = |cells: &[f64], a: Arr, i: usize| cells[at(a, i)];
    let charge = |budget: &mut u64, n: u64| match budget.checked_sub(n) {
        Some(left) => {
            *budget = left;
            Ok(())
        }
        None => Err(LibStop::Budget),
    };
    let x = arrs.first().copied().unwrap_or_default();
    let dim3 = x.len == 3;
    // d = X − C for a primitive with a centre.
    let d = |cells: &[f64]| {
        let c = arrs[1];
        [0, 1, 2].map(|i| get(cells, x, i) - get(cells, c, i))
    };
    let value = match lib {
        Sphere | CylinderX | CylinderY | CylinderZ | ConeX | ConeY | ConeZ if !dim3 => SENTINEL,
        Sphere => {
            let [xt, yt, zt] = d(cells);
            r[0] * r[0] - xt * xt - yt * yt - zt * zt
        }
        CylinderX | CylinderY | CylinderZ => {
            let [xt, yt, zt] = d(cells);
            let (u, v) = match lib {
                CylinderX => (yt, zt),
                CylinderY => (xt, zt),
                _ => (xt, yt),
            };
            r[0] * r[0] - u * u - v * v
        }
        ConeX | ConeY | ConeZ => {
            let [xt, yt, zt] = d(cells);
            let rr = r[0];
            match lib {
                ConeX => sq(xt) - sq(yt / rr) - sq(zt / rr),
                ConeY => sq(yt) - sq(xt / rr) - sq(zt / rr),
                _ => sq(zt) - sq(xt / rr) - sq(yt / rr),
            }
        }
        Ellipsoid => {
            let [a, b, c] = [r[0], r[1], r[2]];
            if !dim3 || a.abs() < EPS || b.abs() < EPS || c.abs() < EPS {
                SENTINEL
            } else {
                let [xt, yt, zt] = d(cells);
                let (xt, yt, zt) = (xt / a, yt / b, zt / c);
                1.0 - xt * xt - yt * yt - zt * zt
            }
        }
        EllCylX | EllCylY | EllCylZ => {
            let [a, b] = [r[0], r[1]];
            if !dim3 || a.abs() < EPS || b.abs() < EPS {
                SENTINEL
            } else {
                let [xt, yt, zt] = d(cells);
                let (u, v) = match lib {
                    EllCylX => (yt, zt),
                    EllCylY => (xt, zt),
                    _ => (xt, yt),
                };
                let (u, v) = (u / a, v / b);
                1.0 - u * u - v * v
            }
        }
        EllConeX | EllConeY | EllConeZ if !dim3 => SENTINEL,
        EllConeX | EllConeY | EllConeZ => {
            let [a, b] = [r[0], r[1]];
            let [xt, yt, zt] = d(cells);
            match lib {
                EllConeX => sq(xt) - sq(yt / a) - sq(zt / b),
                EllConeY => sq(yt) - sq(xt / a) - sq(zt / b),
                _ => sq(zt) - sq(xt / a) - sq(yt / b),
            }
        }
        TorusX | TorusY | TorusZ if !dim3 => SENTINEL,
        TorusX | TorusY | TorusZ => {
            let (big, r0) = (r[0], r[1]);
            let [xt, yt, zt] = d(cells);
            let (x2, y2, z2) = (xt * xt, yt * yt, zt * zt);
            let ring = match lib {
                TorusX => sqrt(z2 + y2),
                TorusY => sqrt(z2 + x2),
                _ => sqrt(x2 + y2),
            };
            r0 * r0 - x2 - y2 - z2 - big * big + 2.0 * big * ring
        }
        Block => {
            let [dx, dy, dz] = [r[0], r[1], r[2]];
            if !dim3 || dx < 0.0 || dy < 0.0 || dz < 0.0 {
                SENTINEL
            } else {
                let v = arrs[1];
                let t = |i: usize, w: f64| {
                    let (xi, vi) = (get(cells, x, i), get(cells, v, i));
                    (xi - vi) * (vi + w - xi)
                };
                let (xt, yt, zt) = (t(0, dx), t(1, dy), t(2, dz));
                let f = xt + yt - sqrt(xt * xt + yt * yt - 2.0 * ALPHA * xt * yt);
                f + zt - sqrt(f * f + zt * zt - 2.0 * ALPHA * f * zt)
            }
        }
        Superell => superell(r, dim3, d(cells)),
        BlendUni | BlendInt => {
            let [f1, f2, a0, a1, a2] = [r[0], r[1], r[2], r[3], r[4]];
            let d = a0 / (1.0 + (f1 / a1) * (f1 / a1) + (f2 / a2) * (f2 / a2));
            let root = sqrt(f1 * f1 + f2 * f2);
            if lib == BlendUni {
                f2 + f1 + root + d
            } else {
                f2 + f1 - root + d
            }
        }
        Blobby | Metaball | Soft => {
            let n = arrs[1].len as usize;
            charge(budget, n as u64)?;
            let p = |i: usize, k: usize| get(cells, arrs[k], i);
            let mut sum = 0.0;
            for i in 0..n {
                let xt = get(cells, x, 0) - p(i, 1);
                let yt = get(cells, x, 1) - p(i, 2);
                let zt = get(cells, x, 2) - p(i, 3);
                let r2 = xt * xt + yt * yt + zt * zt;
                sum = match lib {
                    Blobby => sum + p(i, 5) * libm::exp(-p(i, 4) * r2),
                    Metaball => metaball(sum, r2, p(i, 4), p(i, 5)),
                    _ => soft(sum, r2, p(i, 4)),
                };
            }
            sum - r[0]
        }
        ConvPoint | ConvLine | ConvTriangle if !dim3 => SENTINEL,
        ConvPoint => {
            let (v, s) = (arrs[1], arrs[2]);
            charge(budget, u64::from(s.len))?;
            let mut f = 0.0;
            for n in 0..s.len as usize {
                let r2 = sq(get(cells, v, 3 * n) - get(cells, x, 0))
                    + sq(get(cells, v, 3 * n + 1) - get(cells, x, 1))
                    + sq(get(cells, v, 3 * n + 2) - get(cells, x, 2));
                f += 1.0 / sq(1.0 + sq(get(cells, s, n)) * r2);
            }
            f - r[0]
        }
        ConvLine => {
            let (b, e, s) = (arrs[1], arrs[2], arrs[3]);
            charge(budget, u64::from(s.len))?;
            let mut f = 0.0;
            let p = [0, 1, 2].map(|i| get(cells, x, i));
            for n in 0..s.len as usize {
                let b = [0, 1, 2].map(|i| get(cells, b, 3 * n + i));
                let e = [0, 1, 2].map(|i| get(cells, e, 3 * n + i));
                f += conv_line(p, b, e, get(cells, s, n)).ok_or_else(|| {
                    LibStop::Undefined(format!(
                        "hfConvLine: segment {} has both ends at one point (HyperFun stops \
                         with \"Tips of the segment take same coordinate!\")",
                        n + 1
                    ))
                })?;
            }
            f - r[0]
        }
        ConvTriangle => {
            let (v, s) = (arrs[1], arrs[2]);
            charge(budget, u64::from(s.len))?;
            let mut f = 0.0;
            let p = [0, 1, 2].map(|i| get(cells, x, i));
            for n in 0..s.len as usize {
                let t = core::array::from_fn(|i| get(cells, v, 9 * n + i));
                f += conv_triangle(p, t, get(cells, s, n));
            }
            f - r[0]
        }
        BezierVolume => bezier_volume(r, arrs, cells, budget)?,
        NoiseG if !dim3 => SENTINEL,
        NoiseG => {
            let (a1, a2, phase) = (r[0], r[1], r[2]);
            let [a2x, a2y, a2z] = [0, 1, 2].map(|i| a2 * get(cells, x, i));
            let (sx, sy, sz) = (libm::sin(a2x), libm::sin(a2y), libm::sin(a2z));
            let a1d = a1 / 1.17;
            let sx2 = a1d * libm::sin(a2x / 1.35 + phase * sz);
            let sy2 = a1d * libm::sin(a2y / 1.35 + phase * sx);
            let sz2 = a1d * libm::sin(a2z / 1.35 + phase * sy);
            (a1 * sx + sx2) * (a1 * sy + sy2) * (a1 * sz + sz2)
        }
        Scale3D | Shift3D => {
            for i in 0..3 {
                let c = &mut cells[at(x, i)];
                *c = if lib == Scale3D { *c / r[i] } else { *c - r[i] };
            }
            1.0
        }
        Rotate3DX | Rotate3DY | Rotate3DZ => {
            rotate(cells, x, lib, r[0]);
            1.0
        }
        TwistX | TwistY | TwistZ => {
            let along = match lib {
                TwistX => 0,
                TwistY => 1,
                _ => 2,
            };
            let [x1, x2, theta1, theta2] = [r[0], r[1], r[2], r[3]];
            let t = (get(cells, x, along) - x1) / (x2 - x1);
            let theta = (1.0 - t) * theta1 + t * theta2;
            let turn = [Rotate3DX, Rotate3DY, Rotate3DZ][along];
            rotate(cells, x, turn, theta);
            1.0
        }
        TaperX | TaperY | TaperZ => {
            let (along, first, second) = match lib {
                TaperX => (0, 1, 2),
                TaperY => (1, 2, 0),
                _ => (2, 0, 1),
            };
            let [x1, x2, s1, s2] = [r[0], r[1], r[2], r[3]];
            let xa = get(cells, x, along);
            let mut scale = if xa < x1 {
                s1
            } else if xa > x2 {
                s2
            } else {
                let t = (xa - x1) / (x2 - x1);
                (1.0 - t) * s1 + t * s2
            };
            if scale.abs() < EPS {
                scale = 1.0;
            }
            cells[at(x, first)] /= scale;
            cells[at(x, second)] /= scale;
            1.0
        }
        Stretch3D => {
            // Item by item, so that `hfStretch3D(x, x, …)` reads as HyperFun's loop does.
            let x0 = arrs[1];
            for i in 0..3 {
                let o = get(cells, x0, i);
                cells[at(x, i)] = o + (get(cells, x, i) - o) / r[i];
            }
            1.0
        }
        Clamp => {
            let [v, a, b] = [r[0], r[1], r[2]];
            if v < a {
                a
            } else if v > b {
                b
            } else {
                v
            }
        }
        Floor => f64::from(c_int(r[0])),
        Pulse => {
            // The library reads its second argument as the upper end, its third as the lower.
            let [v, b, a] = [r[0], r[1], r[2]];
            if v < a || v > b { 0.0 } else { 1.0 }
        }
        Step => {
            if r[0] < r[1] {
                0.0
            } else {
                1.0
            }
        }
        Modulo => {
            let (mut a, b) = (r[0], r[1]);
            let n = c_int(a / b);
            a -= f64::from(n) * b;
            if a < 0.0 {
                a += b;
            }
            a
        }
        Sawtooth => {
            let (t, n, a, f) = (r[0], c_int(r[1]), r[2], r[3]);
            if n <= 1 {
                0.0
            } else {
                charge(budget, u64::from(n.unsigned_abs()))?;
                let pi = core::f64::consts::PI;
                let mut res = 0.5;
                for ni in 1..n {
                    let di = f64::from(ni);
                    res -= libm::sin(2.0 * pi * di * f * t) / di;
                }
                res * (2.0 / (a * pi))
            }
        }
    };
    Ok(value)
}

/// `hfSuperell(X, C, a, b, c, s1, s2)`.
fn superell(r: &[f64], dim3: bool, d: [f64; 3]) -> f64 {
    let [a, b, c, s1, s2] = [r[0], r[1], r[2], r[3], r[4]];
    if !dim3 || [a, b, c, s1, s2].iter().any(|v| v.abs() < EPS) {
        return SENTINEL;
    }
    let (xt, yt, zt) = (d[0] / a, d[1] / b, d[2] / c);
    let p = 2.0 / s2;
    let xp = libm::pow(xt.abs(), p);
    let yp = libm::pow(yt.abs(), p);
    let zp = libm::pow(zt.abs(), 2.0 / s1);
    let xyp = libm::pow(xp + yp, s2 / s1);
    1.0 - xyp - zp
}

/// One term of `hfMetaball`, added to `sum`.
fn metaball(sum: f64, r2: f64, b: f64, d: f64) -> f64 {
    if d <= 0.0 || d.is_nan() {
        return sum;
    }
    let r = sqrt(r2);
    let rd = r / d;
    if r <= d / 3.0 {
        sum + b * (1.0 - 3.0 * rd * rd)
    } else if r < d {
        sum + 1.5 * b * (1.0 - rd) * (1.0 - rd)
    } else {
        sum
    }
}

/// One term of `hfSoft`, added to `sum`.
fn soft(sum: f64, r2: f64, d: f64) -> f64 {
    let r4 = r2 * r2;
    let d2 = d * d;
    let d4 = d2 * d2;
    if sqrt(r2) <= d {
        sum + 1.0 - 22.0 * r2 / (9.0 * d2) + 17.0 * r4 / (9.0 * d4)
            - 4.0 * r4 * r2 / (9.0 * d4 * d2)
    } else {
        sum
    }
}

/// `hfRotate3DX/Y/Z` of the array `x` by `theta`.
fn rotate(cells: &mut [f64], x: Arr, axis: Lib, theta: f64) {
    let (i, j) = match axis {
        Lib::Rotate3DX => (1, 2),
        Lib::Rotate3DY => (2, 0),
        _ => (0, 1),
    };
    let (ct, st) = (libm::cos(theta), libm::sin(theta));
    let (ci, cj) = (x.base as usize + i, x.base as usize + j);
    let (u, v) = (cells[ci], cells[cj]);
    cells[ci] = u * ct + v * st;
    cells[cj] = -u * st + v * ct;
}

/// One segment's term of `hfConvLine` (Cauchy line convolution), `None` for a segment of length 0.
fn conv_line(x: [f64; 3], b: [f64; 3], e: [f64; 3], s: f64) -> Option<f64> {
    let l = sqrt(sq(e[0] - b[0]) + sq(e[1] - b[1]) + sq(e[2] - b[2]));
    if l == 0.0 {
        return None;
    }
    let [ax, ay, az] = [0, 1, 2].map(|i| (e[i] - b[i]) / l);
    let [dx, dy, dz] = [0, 1, 2].map(|i| x[i] - b[i]);
    let xx = dx * ax + dy * ay + dz * az;
    let p = sqrt(1.0 + s * s * (dx * dx + dy * dy + dz * dz - xx * xx));
    let q = sqrt(1.0 + s * s * (dx * dx + dy * dy + dz * dz + l * l - 2.0 * l * xx));
    Some(
        xx / (2.0 * p * p * (p * p + s * s * xx * xx))
            + (l - xx) / (2.0 * p * p * q * q)
            + (libm::atan(s * xx / p) + libm::atan(s * (l - xx) / p)) / (2.0 * s * p * p * p),
    )
}

/// One triangle's term of `hfConvTriangle` (Cauchy triangle convolution), vertices `t`.
fn conv_triangle(x: [f64; 3], t: [f64; 9], s: f64) -> f64 {
    let len = |p: [f64; 3], q: [f64; 3]| sqrt(sq(q[0] - p[0]) + sq(q[1] - p[1]) + sq(q[2] - p[2]));
    let (mut a1, mut a2, mut a3) = ([t[0], t[1], t[2]], [t[3], t[4], t[5]], [t[6], t[7], t[8]]);
    let l = [len(a1, a2), len(a2, a3), len(a3, a1)];
    if l[1] >= l[2] && l[1] > l[0] {
        (a1, a2, a3) = (a2, a3, a1);
    } else if l[2] >= l[1] && l[2] > l[0] {
        (a1, a2, a3) = (a3, a1, a2);
    }
    let l0 = len(a1, a2);
    let a21 = [0, 1, 2].map(|i| a2[i] - a1[i]);
    let a13 = [0, 1, 2].map(|i| a1[i] - a3[i]);
    let t = -(a21[0] * a13[0] + a21[1] * a13[1] + a21[2] * a13[2]) / sq(l0);
    let bp = [0, 1, 2].map(|i| a1[i] + t * a21[i]);
    let d = [0, 1, 2].map(|i| x[i] - bp[i]);
    let unit = |p: [f64; 3]| {
        let w = [0, 1, 2].map(|i| p[i] - bp[i]);
        let n = sqrt(sq(w[0]) + sq(w[1]) + sq(w[2]));
        w.map(|c| c / n)
    };
    let (uv, vv) = (unit(a2), unit(a3));
    let d2 = sq(d[0]) + sq(d[1]) + sq(d[2]);
    let u = d[0] * uv[0] + d[1] * uv[1] + d[2] * uv[2];
    let v = d[0] * vv[0] + d[1] * vv[1] + d[2] * vv[2];
    let (h, a1l, a2l) = (len(bp, a3), len(bp, a1), len(bp, a2));
    let g = v - h;
    let m = a2l * g + u * h;
    let k = u * h - a1l * g;
    let c2 = 1.0 / sq(s) + d2 - sq(u);
    let c = sqrt(c2);
    let q = c2 - sq(v);
    let w = c2 - 2.0 * v * h + sq(h);
    let a = sqrt(sq(a1l) * w + sq(h) * (q + sq(u)) - 2.0 * a1l * h * u * g);
    let b = sqrt(sq(a2l) * w + sq(h) * (q + sq(u)) + 2.0 * a2l * h * u * g);
    let n1 = a1l + u;
    let n2 = a2l - u;
    let n3 = a1l * n1 + v * h;
    let n4 = -a1l * u - g * h;
    let n5 = -a2l * n2 - v * h;
    let n6 = -a2l * u + g * h;
    let arc1 = k * (libm::atan(n3 / a) + libm::atan(n4 / a)) / a;
    let arc2 = m * (libm::atan(n5 / b) + libm::atan(n6 / b)) / b;
    let arc3 = v * (libm::atan(n1 / c) + libm::atan(n2 / c)) / c;
    (arc1 + arc2 + arc3) / (2.0 * q * s)
}

/// The most control points per axis `hfBezierVolume` takes (its binomial table stops at 20).
const BEZIER_MAX: i32 = 21;

/// `hfBezierVolume(X, l, m, n, bbox, w)`: the Bernstein sum over the box (its second and third
/// bases taken at the z and y parameters, as the library does), intersected with the box's
/// clipping `(b₁ − x)(x − b₀)`.
fn bezier_volume(r: &[f64], arrs: &[Arr], cells: &[f64], budget: &mut u64) -> Result<f64, LibStop> {
    let (x, bbox, w) = (arrs[0], arrs[1], arrs[2]);
    let [l, m, n] = [r[0], r[1], r[2]].map(c_int);
    if x.len != 3 {
        return Ok(SENTINEL);
    }
    if [l, m, n].iter().any(|&k| k > BEZIER_MAX) {
        return Err(LibStop::Undefined(format!(
            "hfBezierVolume takes at most {BEZIER_MAX} control points per axis, not {l}, {m}, {n} \
             (HyperFun reads past its binomial table)"
        )));
    }
    let count = [l, m, n].map(|k| k.max(0) as usize);
    let total = count[0] * count[1] * count[2];
    if total > w.len as usize {
        return Err(LibStop::Undefined(format!(
            "hfBezierVolume({l}, {m}, {n}) reads {total} control values, its array has {} \
             (HyperFun reads past its end)",
            w.len
        )));
    }
    *budget = budget
        .checked_sub(total as u64 + 1)
        .ok_or(LibStop::Budget)?;
    let get = |a: Arr, i: usize| cells[a.base as usize + i];
    let b = |i: usize| get(bbox, i);
    let p = [0, 1, 2].map(|i| get(x, i));
    let param = |i: usize| (p[i] - b(i)) / (b(i + 3) - b(i));
    let (xt, yt, zt) = (param(0), param(1), param(2));
    let basis = |k: usize, t: f64| -> [f64; BEZIER_MAX as usize] {
        let mut out = [0.0; BEZIER_MAX as usize];
        for (i, o) in out.iter_mut().enumerate().take(k) {
            let deg = k - 1;
            *o = crate::bernstein::binomial(deg, i)
                * libm::pow(1.0 - t, (deg - i) as f64)
                * libm::pow(t, i as f64);
        }
        out
    };
    let (bu, bv, bw) = (
        basis(count[0], xt),
        basis(count[1], zt),
        basis(count[2], yt),
    );
    let (cm, cn) = (count[1], count[2]);
    let mut sum = 0.0;
    for (i, u) in bu.iter().enumerate().take(count[0]) {
        for (j, v) in bv.iter().enumerate().take(cm) {
            for (k, t) in bw.iter().enumerate().take(cn) {
                sum += u * v * t * get(w, i * cm * cn + j * cn + k);
            }
        }
    }
    let rint = |a: f64, b: f64| a + b - sqrt(a * a + b * b);
    let clip = |i: usize| (b(i + 3) - p[i]) * (p[i] - b(i));
    Ok(rint(rint(rint(clip(0), clip(1)), clip(2)), sum))
}
