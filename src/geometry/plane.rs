//! The working planes of G2/G3 (G17, G18, G19) and their axes.

use serde::{Deserialize, Serialize};

/// Working plane of G2/G3 (G17, G18, G19).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Plane {
    #[default]
    XY,
    XZ,
    YZ,
}

impl Plane {
    /// Axis indices (a, b, normal) of the plane, right-handed (a × b = normal) so that G3 is a
    /// positive rotation about the normal, turning from a towards b: G17 (X, Y, Z), G18 (Z, X,
    /// Y), G19 (Y, Z, X).
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::XZ => (2, 0, 1),
            Plane::YZ => (1, 2, 0),
        }
    }
}
