//! Feed profiles: the law s(t) along one block, from `v_in` to `v_out` through the feed `v_feed`,
//! within the path limits. Every law here keeps acceleration zero at block ends (seed 004).
//!
//! Each law lives in its own file and provides the same five functions:
//! - `plan(&BlockRequest) -> <Law>`: the block's profile (a plain record, closed form in t);
//! - `ramp_distance(v1, v2, &Limits)`: distance of the fastest speed change v1 → v2 (a = 0 at both ends);
//! - `max_entry(length, v_out, &Limits)`: largest v_in ≥ v_out whose ramp down to v_out fits in `length`;
//! - `max_exit(length, v_in, &Limits)`: largest v_out ≥ v_in whose ramp up from v_in fits in `length`;
//! - `lowest_exit(length, v_in, target, &Limits)`: largest exit ≤ target whose ramp down fits, when a
//!   stop does.
//!
//! The look-ahead planner only uses these, so every law plans real blocks the same way.

use serde::{Deserialize, Serialize};

pub mod bands;
pub mod compose;
pub mod jerk15;
pub mod mixed57;
pub mod quintic;
pub mod roots;
pub mod scurve7;
pub mod scurve7_banded;
pub mod tolerance;
pub mod trapezoid;

/// Kinematic state along the path at one instant: s (m), v (m/s), a (m/s²), j (m/s³).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Kin {
    pub s: f64,
    pub v: f64,
    pub a: f64,
    pub j: f64,
}

/// Path-level limits for one block (already projected from the axis limits by `path`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// m/s
    pub v_max: f64,
    /// m/s²
    pub a_max: f64,
    /// m/s³
    pub j_max: f64,
    /// m/s⁴ (jerk15 only)
    pub snap_max: f64,
}

/// The acc/dec law, chosen by `profile` in the machine file and `machine.profile` in the FMU.
///
/// The names (machine file, CLI `--kind`, FMU Enumeration items) are strum's, from the variant
/// names; serde's attribute spells the same rule for the TOML reader (a test checks they agree).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Serialize,
    Deserialize,
    strum::IntoStaticStr,
    strum::EnumString,
    strum::VariantArray,
)]
#[serde(rename_all = "lowercase")]
#[strum(serialize_all = "lowercase")]
pub enum ProfileKind {
    #[default]
    Scurve7,
    Quintic,
    Jerk15,
    Mixed57,
    Trapezoid,
}

impl ProfileKind {
    /// Every law, in the FMU Enumeration's order (strum's list, as an array).
    pub const ALL: [ProfileKind; 5] = variants(<ProfileKind as strum::VariantArray>::VARIANTS);

    pub fn name(self) -> &'static str {
        self.into()
    }

    /// What the law is (the FMU's Enumeration item description).
    pub fn description(self) -> &'static str {
        match self {
            ProfileKind::Scurve7 => "7-phase jerk-limited S-curve (Pessoles et al.)",
            ProfileKind::Quintic => "quintic polynomial feedrate (Chen et al.)",
            ProfileKind::Jerk15 => "15-phase jerk-continuous law (Ji et al.)",
            ProfileKind::Mixed57 => "mixed 7/5-period S-curve (Zhang et al.)",
            ProfileKind::Trapezoid => "linear acceleration/deceleration",
        }
    }

    pub fn from_name(name: &str) -> Option<ProfileKind> {
        name.parse().ok()
    }
}

/// strum's `VARIANTS` slice as an array; a length that does not match fails the build.
pub(crate) const fn variants<T: Copy, const N: usize>(all: &[T]) -> [T; N] {
    assert!(all.len() == N, "variant count");
    let mut out = [all[0]; N];
    let mut i = 1;
    while i < N {
        out[i] = all[i];
        i += 1;
    }
    out
}

/// What one block asks of the feed law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BlockRequest {
    /// Block length L (m).
    pub length: f64,
    /// Entry speed V_In (m/s), acceleration zero.
    pub v_in: f64,
    /// Wanted exit speed V_Out (m/s); the profile reports the one actually reached.
    pub v_out: f64,
    /// Programmed feed V_F (m/s), the cruise speed if reachable.
    pub v_feed: f64,
    pub limits: Limits,
}

/// The behaviour every profile record shares.
pub trait FeedLaw {
    /// Total duration (s).
    fn duration(&self) -> f64;
    /// Distance covered (m); equals the block length unless the request was impossible.
    fn length(&self) -> f64;
    /// Exit speed actually reached (m/s).
    fn v_end(&self) -> f64;
    /// State at time t ∈ [0, duration] (clamped outside).
    fn at(&self, t: f64) -> Kin;
    /// Phase durations (s), in order (7 for scurve7, 15 for jerk15, ...).
    fn phases(&self) -> Vec<f64>;
}

/// One block's profile, whatever the law: a plain record, evaluated in closed form.
// Kept inline (no Box): one allocation per planned block would cost more than the bytes.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Profile {
    Scurve7(scurve7::Scurve7),
    Quintic(quintic::Quintic),
    Jerk15(jerk15::Jerk15),
    Mixed57(mixed57::Mixed57),
    Trapezoid(trapezoid::Trapezoid),
    /// scurve7 across speed bands (a block with `Bands`).
    Scurve7Banded(scurve7_banded::Scurve7Banded),
}

macro_rules! dispatch {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            Profile::Scurve7($p) => $e,
            Profile::Quintic($p) => $e,
            Profile::Jerk15($p) => $e,
            Profile::Mixed57($p) => $e,
            Profile::Trapezoid($p) => $e,
            Profile::Scurve7Banded($p) => $e,
        }
    };
}

impl Profile {
    pub fn plan(kind: ProfileKind, req: &BlockRequest) -> Profile {
        match kind {
            ProfileKind::Scurve7 => Profile::Scurve7(scurve7::plan(req)),
            ProfileKind::Quintic => Profile::Quintic(quintic::plan(req)),
            ProfileKind::Jerk15 => Profile::Jerk15(jerk15::plan(req)),
            ProfileKind::Mixed57 => Profile::Mixed57(mixed57::plan(req)),
            ProfileKind::Trapezoid => Profile::Trapezoid(trapezoid::plan(req)),
        }
    }
}

impl Profile {
    /// A restored profile: of the machine's law, its duration, phases, length and exit speed
    /// ones a plan gives (finite everywhere: `crate::valid::numbers`).
    pub fn check_state(&self, kind: ProfileKind) -> Result<(), String> {
        use crate::valid::{within, MAX_SPEED_M_S};
        let same = matches!(
            (self, kind),
            (
                Profile::Scurve7(_) | Profile::Scurve7Banded(_),
                ProfileKind::Scurve7
            ) | (Profile::Quintic(_), ProfileKind::Quintic)
                | (Profile::Jerk15(_), ProfileKind::Jerk15)
                | (Profile::Mixed57(_), ProfileKind::Mixed57)
                | (Profile::Trapezoid(_), ProfileKind::Trapezoid)
        );
        if !same {
            return Err(format!("a profile of another law than the machine's {kind:?}"));
        }
        let most = crate::valid::MAX_TIME_S;
        if let Profile::Scurve7Banded(p) = self {
            p.check_state()?;
        }
        within("profile duration", self.duration(), 0.0, most)?;
        for t in self.phases() {
            within("profile phase", t, 0.0, most)?;
        }
        within(
            "profile length",
            self.length(),
            0.0,
            crate::valid::MAX_POSITION_M * 1e5,
        )?;
        within("profile exit speed", self.v_end(), 0.0, MAX_SPEED_M_S)
    }
}

impl FeedLaw for Profile {
    fn duration(&self) -> f64 {
        dispatch!(self, p => p.duration())
    }
    fn length(&self) -> f64 {
        dispatch!(self, p => p.length())
    }
    fn v_end(&self) -> f64 {
        dispatch!(self, p => p.v_end())
    }
    fn at(&self, t: f64) -> Kin {
        dispatch!(self, p => p.at(t))
    }
    fn phases(&self) -> Vec<f64> {
        dispatch!(self, p => p.phases())
    }
}

/// Distance of the fastest speed change v1 → v2 with the given law (a = 0 at both ends).
pub fn ramp_distance(kind: ProfileKind, v1: f64, v2: f64, lim: &Limits) -> f64 {
    match kind {
        ProfileKind::Scurve7 => scurve7::ramp_distance(v1, v2, lim),
        ProfileKind::Quintic => quintic::ramp_distance(v1, v2, lim),
        ProfileKind::Jerk15 => jerk15::ramp_distance(v1, v2, lim),
        ProfileKind::Mixed57 => mixed57::ramp_distance(v1, v2, lim),
        ProfileKind::Trapezoid => trapezoid::ramp_distance(v1, v2, lim),
    }
}

/// Largest entry speed v_in ≥ v_out from which the law can slow to v_out within `length`.
pub fn max_entry(kind: ProfileKind, length: f64, v_out: f64, lim: &Limits) -> f64 {
    match kind {
        ProfileKind::Scurve7 => scurve7::max_entry(length, v_out, lim),
        ProfileKind::Quintic => quintic::max_entry(length, v_out, lim),
        ProfileKind::Jerk15 => jerk15::max_entry(length, v_out, lim),
        ProfileKind::Mixed57 => mixed57::max_entry(length, v_out, lim),
        ProfileKind::Trapezoid => trapezoid::max_entry(length, v_out, lim),
    }
}

/// Largest exit x ≤ `target` whose ramp from `v_in` fits in `length`, when a stop fits (0 if not).
/// d(v_in, x) is not monotone in x (slowing from v to v/3 can take longer than stopping): this is
/// the crossing on its rising side, in closed form where the law has one.
pub fn lowest_exit(kind: ProfileKind, length: f64, v_in: f64, target: f64, lim: &Limits) -> f64 {
    match kind {
        ProfileKind::Scurve7 => scurve7::lowest_exit(length, v_in, target, lim),
        ProfileKind::Quintic => quintic::lowest_exit(length, v_in, target, lim),
        ProfileKind::Jerk15 => jerk15::lowest_exit(length, v_in, target, lim),
        ProfileKind::Mixed57 => mixed57::lowest_exit(length, v_in, target, lim),
        // d(v_in, x) = (v_in² − x²)/2A falls as x rises: the target fits whenever a stop does.
        ProfileKind::Trapezoid => {
            if trapezoid::ramp_distance(v_in, target, lim) <= length {
                target
            } else {
                0.0
            }
        }
    }
}

/// Largest exit speed v_out ≥ v_in the law can reach from v_in within `length`.
pub fn max_exit(kind: ProfileKind, length: f64, v_in: f64, lim: &Limits) -> f64 {
    match kind {
        ProfileKind::Scurve7 => scurve7::max_exit(length, v_in, lim),
        ProfileKind::Quintic => quintic::max_exit(length, v_in, lim),
        ProfileKind::Jerk15 => jerk15::max_exit(length, v_in, lim),
        ProfileKind::Mixed57 => mixed57::max_exit(length, v_in, lim),
        ProfileKind::Trapezoid => trapezoid::max_exit(length, v_in, lim),
    }
}

/// `x.min(y)` for a `y` that is not NaN, in one comparison where `min` takes several (and keeps
/// loops out of SIMD lanes): a NaN `x` gives `y` as `min` does, and of equal values it may take
/// the other zero's sign, which moves no comparison, divisor or sum where it is used (the
/// envelopes' speeds, the curves' budgets).
#[inline(always)]
pub(crate) fn lesser(x: f64, y: f64) -> f64 {
    if x < y {
        x
    } else {
        y
    }
}

/// `x.max(y)` likewise (`lesser`).
#[inline(always)]
pub(crate) fn greater(x: f64, y: f64) -> f64 {
    if x > y {
        x
    } else {
        y
    }
}
