//! The paper's scripts, as printed (trailing spaces aside), and the examples built from them: each
//! example is the scripts it needs, in order, and a few added lines where the paper's script only
//! defines maps and a figure needs them drawn.

/// One of the paper's scripts.
#[derive(Clone, Copy, Debug)]
pub struct Script {
    /// Its number in the paper, e.g. "4.4".
    pub number: &'static str,
    /// Its caption.
    pub title: &'static str,
    /// The text.
    pub text: &'static str,
}

macro_rules! script {
    ($number:literal, $title:literal) => {
        Script {
            number: $number,
            title: $title,
            text: include_str!(concat!("../scripts/script-", $number, ".psm")),
        }
    };
}

/// Script 3.1, circular arc maps.
pub const S3_1: Script = script!("3.1", "Circular arc maps");
/// Script 3.2, the toolbox.
pub const S3_2: Script = script!("3.2", "Toolbox");
/// Script 3.3, reversing orientation.
pub const S3_3: Script = script!("3.3", "Reversing orientation");
/// Script 4.1, a cubic Bézier plane curve.
pub const S4_1: Script = script!("4.1", "Cubic Bézier curve in the plane");
/// Script 4.2, the transfinite Bézier toolbox.
///
/// Two of its lines are damaged in print. `Bernstein`'s body begins with a `~` that has lost its
/// left operand, read as `* ~` with a warning. `Fact (n::IsNat) = IF:< C:EQ:0, K:1, * ~ INTSTO >`
/// does not apply its `IF` to `n`, where `Choose`, printed just below, ends in `:< n,k >`: as
/// printed (and as PLaSM reads it), `Fact:5` is the function `IF:<…>`, and `Fact:5:5` (or
/// `Fact:m:5` for any `m`) is 120. The paper never calls `Fact` (its `Choose` recurses on itself),
/// so the script runs as printed; the prelude's `Fact` applies the `IF` to `n`, and `Fact:5` is
/// 120 there.
pub const S4_2: Script = script!("4.2", "Transfinite Bézier toolbox");
/// Script 4.3, the dimension-independent transfinite Bézier mapping.
pub const S4_3: Script = script!("4.3", "Dimension-independent transfinite Bézier mapping");
/// Script 4.4, Bézier curves and the surface they blend to.
pub const S4_4: Script = script!("4.4", "Bézier curves and surface");
/// Script 4.5, the dimension-independent transfinite cubic Hermite.
pub const S4_5: Script = script!("4.5", "Dimension-independent transfinite cubic Hermite");
/// Script 4.6, surface by Hermite's interpolation (1).
pub const S4_6: Script = script!("4.6", "Surface by Hermite's interpolation (1)");
/// Script 4.7, surface by Hermite's interpolation (2).
pub const S4_7: Script = script!("4.7", "Surface by Hermite's interpolation (2)");
/// The lines after Fig. 4: `grid1` as the linear transfinite Bézier blend of `c1` and `c2`.
pub const S4_7_BEZIER_GRID: Script = script!("4.7-bezier-grid", "grid1 as a Bézier blend");
/// Script 4.8, examples of planar grids.
pub const S4_8: Script = script!("4.8", "Examples of planar grids");

/// An example of the page's menu and the CLI's `--example`.
#[derive(Clone, Copy, Debug)]
pub struct Example {
    /// A short name: the number of its main script.
    pub id: &'static str,
    /// What it shows.
    pub title: &'static str,
    /// The paper's scripts it runs, in order.
    pub scripts: &'static [Script],
    /// Lines added after them to draw what the scripts only define, if any.
    pub added: &'static str,
}

impl Example {
    /// The whole script: each of the paper's scripts under a comment naming it, then the added
    /// lines under a comment saying they are not in the paper.
    pub fn source(&self) -> String {
        let mut out = String::new();
        for s in self.scripts {
            out.push_str(&format!("% Script {} ({}) %\n", s.number, s.title));
            out.push_str(s.text);
            out.push('\n');
        }
        if !self.added.is_empty() {
            out.push_str("% Added to draw the figure (not in the paper) %\n");
            out.push_str(self.added);
        }
        out
    }
}

/// The examples, one per script of the paper that draws something, and the lines after Fig. 4
/// that make `grid1` a Bézier blend.
pub const EXAMPLES: &[Example] = &[
    Example {
        id: "3.1",
        title: "Circular arcs: three maps, one image",
        scripts: &[S3_2, S3_1],
        added: "",
    },
    Example {
        id: "3.3",
        title: "A quarter circle, reversed",
        scripts: &[S3_2, S3_3],
        added: "",
    },
    Example {
        id: "4.1",
        title: "A cubic Bézier plane curve",
        scripts: &[S4_1],
        added: "MAP:(Bezier3:<<0,0>,<1,2>,<3,2>,<4,0>>):(Domain:32);\n",
    },
    Example {
        id: "4.4",
        title: "Fig. 1: four Bézier curves and their transfinite blend",
        scripts: &[S4_2, S4_3, S4_4],
        added: "MAP:(CONS:C0):(Domain:32);\nMAP:(CONS:C1):(Domain:32);\n\
                MAP:(CONS:C2):(Domain:32);\nMAP:(CONS:C3):(Domain:32);\n",
    },
    Example {
        id: "4.6",
        title: "Fig. 2: Hermite surface, vertical tangents",
        scripts: &[S4_5, S4_8, S4_6],
        added: "",
    },
    Example {
        id: "4.7",
        title: "Fig. 3: Hermite surface, oblique tangents",
        scripts: &[S4_5, S4_8, S4_7],
        added: "",
    },
    Example {
        id: "4.8",
        title: "Fig. 4: three planar grids",
        scripts: &[S4_5, S4_8],
        added: "MAP:(CONS:grid1):(Domain:8 * Domain:8);\n\
                T:1:1.25:(MAP:(CONS:grid2):(Domain:8 * Domain:8));\n\
                T:1:2.5:(MAP:(CONS:grid3):(Domain:8 * Domain:8));\n",
    },
    Example {
        id: "4.7-bezier-grid",
        title: "After Fig. 4: grid1 as the linear Bézier blend of c1 and c2",
        scripts: &[S4_2, S4_3, S4_5, S4_8, S4_7_BEZIER_GRID],
        added: "",
    },
];

/// The example of an id ("4.4").
pub fn example(id: &str) -> Option<&'static Example> {
    EXAMPLES.iter().find(|e| e.id == id)
}
