//! The working planes of G2/G3 (G17, G18, G19) and their axes; G18 and G19 turned about Z
//! with a rotated coordinate system.

use super::{basis, Vec3};
use serde::{Deserialize, Serialize};

/// Working plane of G2/G3 (G17, G18, G19).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Plane {
    #[default]
    XY,
    XZ,
    YZ,
    /// G18 (`yz` false) or G19 (`yz` true) of a coordinate system whose XY axes are turned about
    /// Z (G10 L2 R) by the angle of cosine `cos` and sine `sin`: a vertical plane, not one of
    /// the machine's (LinuxCNC's canon turns the plane's axes with the arc's points).
    Turned {
        yz: bool,
        cos: f64,
        sin: f64,
    },
}

impl Plane {
    /// Axis indices (a, b, normal) of the plane, right-handed (a × b = normal) so that G3 is a
    /// positive rotation about the normal, turning from a towards b: G17 (X, Y, Z), G18 (Z, X,
    /// Y), G19 (Y, Z, X). A turned plane has the indices of its plane before the turn.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::XZ | Plane::Turned { yz: false, .. } => (2, 0, 1),
            Plane::YZ | Plane::Turned { yz: true, .. } => (1, 2, 0),
        }
    }

    /// Unit vectors (a, b, normal) of the plane in machine axes, right-handed as `axes`.
    pub fn basis(self) -> (Vec3, Vec3, Vec3) {
        let (a, b, n) = self.axes();
        let turn = |v: Vec3| match self {
            Plane::Turned { cos, sin, .. } => [cos * v[0] - sin * v[1], sin * v[0] + cos * v[1], v[2]],
            _ => v,
        };
        (turn(basis(a)), turn(basis(b)), turn(basis(n)))
    }

    /// A principal plane (G17, G18, G19 of an unturned system).
    pub fn principal(self) -> bool {
        !matches!(self, Plane::Turned { .. })
    }
}
