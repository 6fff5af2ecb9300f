//! A small deterministic random generator, SplitMix64 (Steele, Lea & Flood 2014): the same
//! sequence on every machine, for procedural scenes and for tests' random cases.

/// SplitMix64: the state advances by a constant and each output is the state mixed. Any seed
/// works, 0 included.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// The next value in `[0, 1)`, from 24 random bits (every such `f32` exactly).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// The next value in `[0, 1)`, from 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next value in `0..n` (`n > 0`; the modulo's bias is below `n / 2^64`).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference outputs of SplitMix64 from seed 1234567 (the published test vector), and
    /// the ranges of the derived values.
    #[test]
    fn splitmix_matches_the_reference_sequence() {
        let mut r = SplitMix(1234567);
        let expect = [
            6457827717110365317,
            3203168211198807973,
            9817491932198370423,
            4593380528125082431,
            16408922859458223821,
        ];
        for e in expect {
            assert_eq!(r.next_u64(), e);
        }
        for _ in 0..1000 {
            let (f, d, b) = (r.next_f32(), r.next_f64(), r.below(7));
            assert!((0.0..1.0).contains(&f) && (0.0..1.0).contains(&d) && b < 7);
        }
    }
}
