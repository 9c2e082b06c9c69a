//! Helpers shared by the unit tests: a small deterministic generator (tests run the same natively and
//! in node, where no OS randomness is needed).

/// The box `[lo, hi]` as 8 corners (corner `i` takes `hi` on axis `k` where bit `k` of `i` is
/// set) and 12 triangles, counter-clockwise seen from outside, its vertices numbered from `base`.
pub(crate) fn box_mesh(
    lo: glam::DVec3,
    hi: glam::DVec3,
    base: u32,
) -> (alloc::vec::Vec<glam::DVec3>, alloc::vec::Vec<[u32; 3]>) {
    let positions = (0..8)
        .map(|i| glam::DVec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo))
        .collect();
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let triangles = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .map(|t| t.map(|i| i + base))
        .collect();
    (positions, triangles)
}

/// xorshift64*: enough for test data, reproducible from its seed.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// Uniform integer in `lo..=hi`.
    pub(crate) fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }
}

/// What [`assert_close!`] compares: numbers, glam vectors and arrays of numbers.
pub(crate) trait Approx: Copy + core::fmt::Debug {
    /// The largest difference of a component.
    fn max_abs_diff(self, other: Self) -> f64;
    /// The largest magnitude of a component.
    fn max_abs(self) -> f64;
}

impl Approx for f64 {
    fn max_abs_diff(self, other: Self) -> f64 {
        (self - other).abs()
    }
    fn max_abs(self) -> f64 {
        self.abs()
    }
}

macro_rules! glam_approx {
    ($($t:ty),*) => {$(
        impl Approx for $t {
            fn max_abs_diff(self, other: Self) -> f64 {
                (self - other).abs().max_element()
            }
            fn max_abs(self) -> f64 {
                self.abs().max_element()
            }
        }
    )*};
}
glam_approx!(glam::DVec2, glam::DVec3, glam::DVec4);

impl<const N: usize> Approx for [f64; N] {
    fn max_abs_diff(self, other: Self) -> f64 {
        self.iter()
            .zip(other)
            .fold(0.0, |m, (a, b)| f64::max(m, (a - b).abs()))
    }
    fn max_abs(self) -> f64 {
        self.iter().fold(0.0, |m, a| f64::max(m, a.abs()))
    }
}

/// Asserts that two numbers, vectors or arrays agree to `tol` relative to the larger of them (and
/// absolutely below magnitude 1): `|a − b| ≤ tol · max(|a|, |b|, 1)`, component by component. An
/// optional message follows, as for `assert!`.
macro_rules! assert_close {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {
        $crate::testutil::assert_close!($a, $b, $tol, "")
    };
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        use $crate::testutil::Approx as _;
        let (a, b, tol) = ($a, $b, $tol);
        let scale = a.max_abs().max(b.max_abs()).max(1.0);
        let diff = a.max_abs_diff(b);
        assert!(
            diff <= tol * scale,
            "{a:?} and {b:?} differ by {diff:e}, more than {tol:e} × {scale:e}: {}",
            format_args!($($msg)+)
        );
    }};
}
pub(crate) use assert_close;

/// A point in the cube `[-r, r]³`.
pub(crate) fn random_point(rng: &mut Rng, r: f64) -> [f64; 3] {
    [rng.range(-r, r), rng.range(-r, r), rng.range(-r, r)]
}

/// A random piecewise volume around the origin (cells and degree 1 to 2 on each axis), a ball-like
/// ξ (positive near the middle), its points moved a little where `moved`.
pub(crate) fn random_piecewise3(rng: &mut Rng, moved: bool) -> crate::model::SolidSpec {
    let cells = [rng.int(1, 2), rng.int(1, 2), rng.int(1, 2)];
    let degree = [rng.int(1, 2), rng.int(1, 2), rng.int(1, 2)];
    let dims: [usize; 3] = core::array::from_fn(|a| cells[a] * degree[a] + 1);
    let c = random_point(rng, 0.3);
    let half = rng.range(0.6, 0.9);
    let points = (0..dims.iter().product())
        .map(|k| {
            let i = crate::tensor::multi_index(dims, k);
            let t: [f64; 3] = core::array::from_fn(|a| i[a] as f64 / (dims[a] - 1) as f64);
            let mut p: alloc::vec::Vec<f64> = (0..3)
                .map(|a| {
                    let wobble = if moved { rng.range(-0.04, 0.04) } else { 0.0 };
                    c[a] - half + 2.0 * half * t[a] + wobble
                })
                .collect();
            let r2: f64 = t.iter().map(|x| (x - 0.5) * (x - 0.5)).sum();
            p.push(0.5 - 2.0 * r2 + rng.range(-0.1, 0.1));
            p
        })
        .collect();
    crate::model::SolidSpec::Piecewise {
        cells: cells.to_vec(),
        degree: degree.to_vec(),
        points,
    }
}

/// A random bounded 3D tree: primitives, regular volumes, operations, blends, morphs and
/// transforms, `depth` levels at most.
pub(crate) fn random_tree(rng: &mut Rng, depth: usize) -> crate::model::SolidSpec {
    use crate::model::{CoordAxis, ModelFile, Rotation, SolidSpec as S};
    use alloc::boxed::Box;
    use alloc::vec;
    let leaf = rng.int(0, 4);
    if depth == 0 || rng.int(0, 3) == 0 {
        return match leaf {
            0 => S::Sphere {
                center: random_point(rng, 0.8),
                radius: rng.range(0.4, 1.0),
            },
            1 => {
                let c = random_point(rng, 0.6);
                let h = [
                    rng.range(0.3, 0.8),
                    rng.range(0.3, 0.8),
                    rng.range(0.3, 0.8),
                ];
                S::Box {
                    min: core::array::from_fn(|i| c[i] - h[i]),
                    max: core::array::from_fn(|i| c[i] + h[i]),
                }
            }
            2 => S::Torus {
                center: random_point(rng, 0.5),
                axis: [CoordAxis::X, CoordAxis::Y, CoordAxis::Z][rng.int(0, 2)],
                major: rng.range(0.6, 0.9),
                minor: rng.range(0.25, 0.4),
            },
            3 => S::Intersection {
                of: vec![
                    S::Cylinder {
                        center: random_point(rng, 0.3),
                        axis: CoordAxis::Z,
                        radius: rng.range(0.3, 0.7),
                    },
                    S::Box {
                        min: [-1.0, -1.0, -0.7],
                        max: [1.0, 1.0, 0.7],
                    },
                ],
            },
            _ => {
                let c = random_point(rng, 0.3);
                let v = crate::Solid3::regular(
                    [2, 2, 2],
                    glam::DVec3::from_array(c) - 0.8,
                    glam::DVec3::from_array(c) + 0.8,
                    |[i, j, k]| if (i, j, k) == (1, 1, 1) { 1.0 } else { -0.2 },
                )
                .unwrap();
                ModelFile::from_solid3(&v).solid
            }
        };
    }
    let two = |rng: &mut Rng| vec![random_tree(rng, depth - 1), random_tree(rng, depth - 1)];
    match rng.int(0, 6) {
        0 => S::Union { of: two(rng) },
        1 => S::Intersection { of: two(rng) },
        2 => S::Difference { of: two(rng) },
        3 => S::BlendUnion {
            of: two(rng),
            a0: rng.range(0.05, 0.3),
            a1: rng.range(0.5, 1.5),
            a2: rng.range(0.5, 1.5),
        },
        4 => S::BlendIntersection {
            of: two(rng),
            a0: rng.range(-0.2, 0.2),
            a1: rng.range(0.5, 1.5),
            a2: rng.range(0.5, 1.5),
        },
        5 => S::Morph {
            of: two(rng),
            t: rng.range(0.0, 1.0),
        },
        _ => S::Transform {
            solid: Box::new(random_tree(rng, depth - 1)),
            translate: Some(random_point(rng, 0.5).to_vec()),
            rotate: Some(Rotation::Angles(random_point(rng, 180.0))),
            scale: Some(vec![
                rng.range(0.6, 1.4),
                rng.range(0.6, 1.4),
                rng.range(0.6, 1.4),
            ]),
        },
    }
}
