//! Nothing here: the comparison is benches/ruckig.rs.
