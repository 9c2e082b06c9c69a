//! The lists read one element at a time and refused past a cap: a mesh's `positions` and
//! `triangles`, a piecewise solid's `points`.

use alloc::vec::Vec;
use core::fmt;
use core::marker::PhantomData;

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};

use crate::mesh::{MAX_TRIANGLES, MAX_VERTICES};

/// A mesh's `positions`, refused past [`MAX_VERTICES`].
pub(in crate::model) fn positions<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Vec<[f64; 3]>, D::Error> {
    d.deserialize_seq(Capped::new(MAX_VERTICES, "vertices"))
}

/// A piecewise solid's `points`, refused past [`crate::piecewise::MAX_POINTS`].
pub(super) fn piecewise_points<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
    d.deserialize_seq(Capped {
        holder: "a piecewise solid",
        taker: "a piecewise solid",
        ..Capped::new(crate::piecewise::MAX_POINTS, "control points")
    })
}

/// A mesh's `triangles`, refused past [`MAX_TRIANGLES`].
pub(in crate::model) fn triangles<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Vec<[u32; 3]>, D::Error> {
    d.deserialize_seq(Capped::new(MAX_TRIANGLES, "triangles"))
}

/// A list of at most `max` elements, read one at a time.
pub(super) struct Capped<T> {
    max: usize,
    what: &'static str,
    /// What holds the list, and what takes at most `max` of them, for the message.
    holder: &'static str,
    taker: &'static str,
    element: PhantomData<T>,
}

impl<T> Capped<T> {
    pub(super) fn new(max: usize, what: &'static str) -> Self {
        Self {
            max,
            what,
            holder: "a mesh",
            taker: "a free-form model",
            element: PhantomData,
        }
    }

    fn too_many<E: de::Error>(&self) -> E {
        E::custom(format_args!(
            "{} has more than {} {} (the most {} takes)",
            self.holder, self.max, self.what, self.taker
        ))
    }
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for Capped<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a list of at most {} {}", self.max, self.what)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        // A format that states the length (postcard) is refused before any element is read.
        if seq.size_hint().is_some_and(|n| n > self.max) {
            return Err(self.too_many());
        }
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
        while let Some(element) = seq.next_element()? {
            if out.len() == self.max {
                return Err(self.too_many());
            }
            out.push(element);
        }
        Ok(out)
    }
}
