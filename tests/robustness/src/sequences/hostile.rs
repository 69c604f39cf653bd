//! Hostile numbers: the real values an importer should never pass (NaN of either sign,
//! infinities, the extremes, subnormals), among a few ordinary ones.

use crate::rng::Rng;

/// One of these numbers, drawn by `rng`.
pub fn hostile_f64(rng: &mut Rng) -> f64 {
    *rng.pick(&[
        f64::NAN,
        -f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        1e308,
        -1e308,
        f64::MAX,
        f64::MIN,
        f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        1e-300,
        -1.0,
        1.0,
        1e6,
        -1e6,
        1e15,
        1e-12,
    ])
}
