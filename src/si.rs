//! The library computes in SI (m, s, m/s, m/s², m/s³); machine files, programs, the CLI and the
//! tests write millimetres and mm/min. The factors, once (below every stage: no imports).

/// One millimetre (m).
pub const MM: f64 = 1e-3;
/// One mm/min (m/s).
pub const MM_MIN: f64 = 1e-3 / 60.0;
