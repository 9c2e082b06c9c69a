//! Meshes and the files they are written to. So far: SVG of 2D contours ([`svg`]).

pub mod svg;
