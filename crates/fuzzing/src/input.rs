//! Reading a fuzzer's bytes as choices and numbers: every read succeeds, with zeros once the bytes
//! run out, so that every input decodes to something and a short input is a simple one.

/// The bytes not yet read.
pub(crate) struct Input<'a> {
    rest: &'a [u8],
}

impl<'a> Input<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Self { rest: data }
    }

    /// The next byte, 0 past the end.
    pub(crate) fn byte(&mut self) -> u8 {
        match self.rest.split_first() {
            Some((&b, rest)) => {
                self.rest = rest;
                b
            }
            None => 0,
        }
    }

    /// A choice among `n` (at least 1): the next byte modulo `n`.
    pub(crate) fn below(&mut self, n: usize) -> usize {
        usize::from(self.byte()) % n.max(1)
    }

    /// An index among `n` (at least 1) from two bytes, for nets of up to 17³ points.
    pub(crate) fn index(&mut self, n: usize) -> usize {
        let hi = usize::from(self.byte());
        let lo = usize::from(self.byte());
        ((hi << 8) | lo) % n.max(1)
    }

    /// A number in [0, 1] from one byte, in steps of 1/255.
    pub(crate) fn unit(&mut self) -> f64 {
        f64::from(self.byte()) / 255.0
    }

    /// A number in [−1, 1] from one byte (as `i8`), in steps of 1/128, 0 included.
    pub(crate) fn signed(&mut self) -> f64 {
        f64::from(self.byte() as i8) / 128.0
    }

    /// Any `f64` from 8 little-endian bytes: NaN, infinities, subnormals and −0 included.
    pub(crate) fn raw_f64(&mut self) -> f64 {
        f64::from_le_bytes(core::array::from_fn(|_| self.byte()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_reads_zeros_past_the_end() {
        let mut input = Input::new(&[7, 0x80, 1, 2]);
        assert_eq!(input.below(4), 3);
        assert_eq!(input.signed(), -1.0);
        assert_eq!(input.index(1000), 258);
        assert_eq!(input.byte(), 0);
        assert_eq!(input.unit(), 0.0);
        assert_eq!(input.raw_f64().to_bits(), 0);
    }
}
