//! Geometry below the data path, in kurbo's manner (small value types with methods named after
//! the geometry): points and vectors in machine axes, the working planes, and the programmed
//! shape of a G-code block — a line, or an arc or helix — with its length and its evaluation by
//! arc length. `gcode` builds these from its words (`Block::geometry`), `path` runs them: neither
//! imports the other for geometry.

mod arc;
mod line;
mod plane;
mod source;
pub mod vec2;
mod vec3;

pub use arc::{Arc, AtAngle};
pub use line::Line;
pub use plane::Plane;
pub use source::{distance_to_segment, Source};
pub use vec3::{add, basis, cross, dot, norm, scale, sub, unit, Vec3};

/// A point of a curve and its derivatives with respect to its arc length s: on a path run at
/// speed v with acceleration a and jerk j, the axis velocity is d1·v, the acceleration
/// d2·v² + d1·a, the jerk d3·v³ + 3·d2·v·a + d1·j.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Geo {
    pub p: Vec3,
    pub d1: Vec3,
    pub d2: Vec3,
    pub d3: Vec3,
}
