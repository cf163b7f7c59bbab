//! In-plane arithmetic on (a, b) coordinates of a working plane (`Plane::axes`): what cutter
//! compensation and the spline-to-biarc reader compute in. Plain functions on `[f64; 2]`, as
//! for Vec3.

/// A point or vector in the plane's axes (a, b) (m).
pub type P2 = [f64; 2];

pub fn sub(p: P2, q: P2) -> P2 {
    [p[0] - q[0], p[1] - q[1]]
}
/// p + s·t: the point at s along t from p.
pub fn along(p: P2, t: P2, s: f64) -> P2 {
    [p[0] + s * t[0], p[1] + s * t[1]]
}
pub fn dot(p: P2, q: P2) -> f64 {
    p[0] * q[0] + p[1] * q[1]
}
/// The z component of p × q.
pub fn cross(p: P2, q: P2) -> f64 {
    p[0] * q[1] - p[1] * q[0]
}
pub fn norm(p: P2) -> f64 {
    p[0].hypot(p[1])
}
pub fn dist(p: P2, q: P2) -> f64 {
    norm(sub(p, q))
}
/// Left normal of a unit tangent.
pub fn left(t: P2) -> P2 {
    [-t[1], t[0]]
}
/// Direction of p seen from c (rad, −π … π).
pub fn angle(c: P2, p: P2) -> f64 {
    (p[1] - c[1]).atan2(p[0] - c[0])
}
