//! A deterministic random number for the library's unit tests (a failure replays); it imports
//! nothing, so any module's tests may use it.

/// Deterministic xorshift64* in [0, 1).
pub fn unit(state: &mut u64) -> f64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
}
