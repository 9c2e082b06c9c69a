//! Preset solids that give recognisable shapes: the first paper's Fig. 9 in 2D, and in 3D a blob, a
//! ring and a fish in the spirit of the paper's Fig. 10 and its "Bézier zoo" (Fig. 12), made by us.

use glam::{DVec2, DVec3};

use crate::model::ModelSolid;
use crate::{Solid2, Solid3};

/// A preset model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Preset {
    /// The paper's Fig. 9: a degree-(2, 2) patch, one blob in the unit square.
    Fig9,
    /// A degree-(2, 2, 2) volume over `[-1, 1]³`: the centre raised, the corners lowered.
    Blob,
    /// A torus-like ring: degree (6, 6, 2) over `[-1, 1]² × [-0.4, 0.4]`, ξ positive on a circle of
    /// control points in the middle layer.
    Ring,
    /// A fish: degree (6, 4, 2) over `[0, 3] × [−0.8, 0.8] × [−0.5, 0.5]`, a round body, a waist and
    /// a tail fin that is wide in y and thin in z.
    Fish,
}

impl Preset {
    /// Every preset, 2D first.
    pub const ALL: [Self; 4] = [Self::Fig9, Self::Blob, Self::Ring, Self::Fish];

    /// The preset's name in files, links and the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Fig9 => "fig9",
            Self::Blob => "blob",
            Self::Ring => "ring",
            Self::Fish => "fish",
        }
    }

    /// The preset called `name`, if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The preset's solid.
    #[must_use]
    pub fn solid(self) -> ModelSolid {
        match self {
            Self::Fig9 => ModelSolid::Patch(Solid2::fig9()),
            Self::Blob => ModelSolid::Volume(blob()),
            Self::Ring => ModelSolid::Volume(ring()),
            Self::Fish => ModelSolid::Volume(fish()),
        }
    }
}

fn valid(solid: Result<Solid3, crate::SolidError>) -> Solid3 {
    solid.unwrap_or_else(|_| unreachable!("presets are valid regular grids"))
}

fn blob() -> Solid3 {
    valid(Solid3::regular(
        [2, 2, 2],
        DVec3::splat(-1.0),
        DVec3::ONE,
        |index| match index {
            [1, 1, 1] => 1.0,
            [0 | 2, 0 | 2, 0 | 2] => -1.0,
            _ => 0.25,
        },
    ))
}

fn ring() -> Solid3 {
    // The middle layer is raised on the control points at radius 0.5 to 1 from the axis and lowered
    // inside (the hole) and outside; the top and bottom layers are lowered a little.
    let min = DVec3::new(-1.0, -1.0, -0.4);
    valid(Solid3::regular([6, 6, 2], min, -min, |[i, j, k]| {
        let r = DVec2::new(i as f64 / 3.0 - 1.0, j as f64 / 3.0 - 1.0).length();
        match (k, r) {
            (1, r) if r > 0.5 && r < 1.0 => 2.0,
            (1, r) if r <= 0.5 => -1.0,
            (1, _) => -0.5,
            _ => -0.3,
        }
    }))
}

fn fish() -> Solid3 {
    // Along x (i): nose, head, belly, back, waist, tail root, tail. Across y (j) the rows are outer,
    // near, centre, near, outer; in z (k) the middle layer and the top/bottom layers. The body is
    // high in the middle layer and not too low above and below (round); the tail is wide in y (the
    // outer rows rise at i = 6) and thin in z (top and bottom well below the middle).
    const MIDDLE: [[f64; 7]; 3] = [
        [-1.0, -1.0, -1.0, -1.0, -1.0, -1.5, 2.6],
        [-1.0, 1.2, 2.4, 2.0, 0.2, 0.8, 1.8],
        [-0.5, 2.5, 3.5, 3.2, 2.6, 3.2, 1.2],
    ];
    const OUTER: [[f64; 7]; 3] = [
        [-1.2, -1.2, -1.2, -1.2, -1.2, -1.2, -2.2],
        [-1.2, -1.2, -1.2, -1.2, -1.2, -1.2, -1.3],
        [-1.0, -0.2, 0.3, 0.0, -1.0, -1.8, -1.0],
    ];
    const ROW: [usize; 5] = [0, 1, 2, 1, 0];
    valid(Solid3::regular(
        [6, 4, 2],
        DVec3::new(0.0, -0.8, -0.5),
        DVec3::new(3.0, 0.8, 0.5),
        |[i, j, k]| {
            let layer = if k == 1 { &MIDDLE } else { &OUTER };
            layer[ROW[j]][i]
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn names_round_trip() {
        for p in Preset::ALL {
            assert_eq!(Preset::from_name(p.name()), Some(p));
        }
        assert_eq!(Preset::from_name("whale"), None);
    }

    #[test]
    fn presets_mesh_to_closed_surfaces_of_the_right_genus() {
        for (preset, euler) in [(Preset::Blob, 2), (Preset::Ring, 0), (Preset::Fish, 2)] {
            let ModelSolid::Volume(solid) = preset.solid() else {
                panic!("{preset:?} is a volume");
            };
            let mesh = solid.polygonize(48, 1e-9).unwrap();
            mesh.check_closed_manifold().unwrap();
            assert_eq!(mesh.euler_characteristic(), euler, "{preset:?}");
            assert!(
                mesh.volume() > 0.0,
                "{preset:?} {} {}",
                mesh.volume(),
                mesh.triangle_count()
            );
        }
    }
}
