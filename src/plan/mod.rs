//! Look-ahead planner: decides each segment's entry and exit speeds over a bounded window.

use crate::feed::Profile;
use crate::path::PathBlock;
use serde::{Deserialize, Serialize};

/// A segment with its speeds decided and its feed profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Planned {
    pub block: PathBlock,
    pub v_in: f64,
    pub v_out: f64,
    pub profile: Profile,
}
