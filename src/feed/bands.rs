//! Speed bands: path limits that grow as the speed falls. On a curve each axis's acceleration is
//! its centripetal part d2·v² plus its tangential part d1·a (and its jerk d3·v³ + 3·d2·v·a +
//! d1·j), so the tangential acceleration and jerk a block may use are larger at lower speeds.
//! Seed 004 (eq. 19–24) evaluates them at one speed; sized for the block's top speed, a ramp from
//! rest wastes most of the axes' acceleration on the way up (a full circle at 250 mm/s on
//! 2000 mm/s² axes ramped at 520 mm/s²).
//!
//! `Bands` lists levels below a block's own limits: band k holds the speeds up to v_k with A_k, J_k,
//! which keep every axis within its limits at any speed up to v_k; the block's limits are the top
//! band. The feed law runs inside each band with that band's limits, acceleration zero at the band
//! edges, so a speed change across bands is the bands' own ramps in turn: every ramp distance, and
//! with it every question the look-ahead asks (`max_entry`, `max_exit`, `lowest_exit`), decomposes
//! band by band, and the planner emits a banded block as one part per band crossed ([`Banded::parts`]).
//! A band's limits hold at every speed below its top, so running slower in a higher band is always
//! within the limits; the decomposition only decides how fast.

use super::{scurve7_banded, BlockRequest, FeedLaw, Limits, Profile, ProfileKind};
use serde::{Deserialize, Serialize};

/// Levels at most below a block's own limits.
pub const MAX_BANDS: usize = 16;

/// The limits that hold at every path speed up to `v_top`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Band {
    pub v_top: f64,
    pub a_max: f64,
    pub j_max: f64,
}

impl Band {
    /// The band's limits, with the snap of `top`.
    pub fn limits(&self, top: &Limits) -> Limits {
        Limits {
            v_max: self.v_top,
            a_max: self.a_max,
            j_max: self.j_max,
            snap_max: top.snap_max,
        }
    }
}

/// Levels below a block's limits, by increasing speed (each with A and J above the next one's).
/// Empty: the block's limits hold at every speed alike (lines), and nothing is allocated.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Bands {
    levels: Vec<Band>,
}

impl Bands {
    /// A restored set: at most MAX_BANDS levels by increasing speed, each with positive limits.
    pub fn check_state(&self) -> Result<(), String> {
        use crate::valid::{at_most, within, MAX_SPEED_M_S};
        at_most("speed bands", self.levels.len() as u64, MAX_BANDS as u64)?;
        let mut below = 0.0;
        for b in &self.levels {
            within("band speed", b.v_top, below, MAX_SPEED_M_S)?;
            within("band acceleration", b.a_max, f64::MIN_POSITIVE, f64::INFINITY)?;
            within("band jerk", b.j_max, f64::MIN_POSITIVE, f64::INFINITY)?;
            below = b.v_top;
        }
        Ok(())
    }

    /// The levels of `levels` below `top`'s speed, by increasing speed (one per speed), at most
    /// `MAX_BANDS` (the fastest ones). A level's pair (A, J) holds as a pair: more acceleration
    /// may leave less jerk, so a band need not have more of both than the one above it.
    pub fn below(top: &Limits, levels: &[Band]) -> Bands {
        Bands::keep_below(top, levels.to_vec())
    }

    /// `below`, kept in `levels` itself (no second list).
    pub fn keep_below(top: &Limits, mut kept: Vec<Band>) -> Bands {
        kept.retain(|b| {
            b.v_top > 0.0
                && b.v_top < top.v_max
                && b.a_max > 0.0
                && b.j_max > 0.0
                && b.a_max.is_finite()
                && b.j_max.is_finite()
        });
        // Curves list their levels by increasing speed already (path/arc.rs): no sort then.
        if !kept.windows(2).all(|w| w[0].v_top < w[1].v_top) {
            kept.sort_by(|x, y| x.v_top.total_cmp(&y.v_top));
            kept.dedup_by(|a, b| a.v_top == b.v_top);
        }
        let skip = kept.len().saturating_sub(MAX_BANDS);
        kept.drain(..skip);
        Bands { levels: kept }
    }

    pub fn len(&self) -> usize {
        self.levels.len()
    }

    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }

    /// The tightest and the widest of the pairs (A, J) of `top` and these levels, each with
    /// `top`'s speed and snap: a ramp within them is no faster than within the first throughout,
    /// nor slower than within the second (a level's pair holds as a pair, so neither need be
    /// one of them).
    pub fn pair_range(&self, top: &Limits) -> (Limits, Limits) {
        self.levels.iter().fold((*top, *top), |(mut tight, mut wide), b| {
            (tight.a_max, tight.j_max) = (tight.a_max.min(b.a_max), tight.j_max.min(b.j_max));
            (wide.a_max, wide.j_max) = (wide.a_max.max(b.a_max), wide.j_max.max(b.j_max));
            (tight, wide)
        })
    }

    pub fn levels(&self) -> &[Band] {
        &self.levels
    }
}

/// A block's limits with its bands, for one feed law: the ramp distances and the look-ahead's
/// questions across bands.
#[derive(Clone, Copy, Debug)]
pub struct Banded<'a> {
    pub kind: ProfileKind,
    pub top: &'a Limits,
    pub bands: &'a Bands,
}

/// One stretch of a banded block, as the planner emits it: [s0, s0 + length] run from `v_in` to
/// `v_out` within `limits` (one band's) by `profile`.
#[derive(Clone, Debug, PartialEq)]
pub struct BandPart {
    pub s0: f64,
    pub length: f64,
    pub limits: Limits,
    pub v_in: f64,
    pub v_out: f64,
    pub v_feed: f64,
    pub profile: Profile,
}

impl Banded<'_> {
    /// The law runs across band edges without a stop of the acceleration (scurve7_banded.rs);
    /// the other laws ramp band by band, acceleration zero at each edge.
    pub fn joined(&self) -> bool {
        self.kind == ProfileKind::Scurve7 && !self.bands.is_empty()
    }

    pub(super) fn count(&self) -> usize {
        self.bands.len() + 1
    }

    /// Limits of band k (the top band is the block's own).
    pub fn limits(&self, k: usize) -> Limits {
        self.bands
            .levels()
            .get(k)
            .map_or(*self.top, |b| b.limits(self.top))
    }

    /// Top speed of band k for the decomposition (∞ for the top band: speeds above the block's
    /// v_max are the top band's too, as the unbanded laws treat them).
    pub(super) fn top_of(&self, k: usize) -> f64 {
        self.bands.levels().get(k).map_or(f64::INFINITY, |b| b.v_top)
    }

    pub(super) fn floor_of(&self, k: usize) -> f64 {
        if k == 0 {
            0.0
        } else {
            self.top_of(k - 1)
        }
    }

    /// The band a speed belongs to, its top included.
    fn band_of(&self, v: f64) -> usize {
        self.bands.levels().iter().take_while(|b| v > b.v_top).count()
    }

    /// Time of the fastest ramp from rest to `v_top` within the worst of these limits and
    /// `other`'s at every speed (`worst_with`), or None where one set's are nowhere above the
    /// other's (the ramp is that set's own).
    pub fn worst_ramp(&self, other: &Banded, v_top: f64) -> Option<f64> {
        let (top, bands) = self.worst_with(other, v_top)?;
        let worst = Banded {
            kind: self.kind,
            top: &top,
            bands: &bands,
        };
        Some(scurve7_banded::ramp_time(&worst, 0.0, v_top))
    }

    /// The worst of these limits and `other`'s at every speed up to `v_top` (a chain's, whose
    /// limits are the worst of its pieces'): on both sets' band edges below it, each band the
    /// least acceleration and jerk of the two there (the fastest `MAX_BANDS` kept). None where
    /// one set's are nowhere above the other's: the worst is that set itself.
    fn worst_with(&self, other: &Banded, v_top: f64) -> Option<(Limits, Bands)> {
        let (xs, ys) = (self.bands.levels(), other.bands.levels());
        let (mut i, mut k) = (0, 0);
        let (mut below, mut above) = (true, true);
        let mut levels = Vec::with_capacity(xs.len() + ys.len());
        // Both sets' edges in increasing order, each band's pair where it ends.
        loop {
            let v = match (xs.get(i), ys.get(k)) {
                (Some(x), Some(y)) => x.v_top.min(y.v_top),
                (Some(x), None) => x.v_top,
                (None, Some(y)) => y.v_top,
                (None, None) => f64::INFINITY,
            }
            .min(v_top);
            let (x, y) = (self.limits(i), other.limits(k));
            below &= x.a_max <= y.a_max && x.j_max <= y.j_max;
            above &= x.a_max >= y.a_max && x.j_max >= y.j_max;
            let (a_max, j_max) = (x.a_max.min(y.a_max), x.j_max.min(y.j_max));
            if v >= v_top {
                if below || above {
                    return None;
                }
                let top = Limits {
                    v_max: v_top,
                    a_max,
                    j_max,
                    snap_max: self.top.snap_max.min(other.top.snap_max),
                };
                return Some((top, Bands::keep_below(&top, levels)));
            }
            levels.push(Band {
                v_top: v,
                a_max,
                j_max,
            });
            i += usize::from(xs.get(i).is_some_and(|b| b.v_top == v));
            k += usize::from(ys.get(k).is_some_and(|b| b.v_top == v));
        }
    }

    /// Distance of the fastest speed change v1 → v2: the bands' ramps between them in turn.
    pub fn ramp_distance(&self, v1: f64, v2: f64) -> f64 {
        let (lo, hi) = (v1.min(v2).max(0.0), v1.max(v2).max(0.0));
        if self.bands.is_empty() {
            return super::ramp_distance(self.kind, lo, hi, self.top);
        }
        if self.joined() {
            return scurve7_banded::ramp_distance(self, lo, hi);
        }
        let mut d = 0.0;
        for k in self.band_of(lo)..self.count() {
            let (a, b) = (lo.max(self.floor_of(k)), hi.min(self.top_of(k)));
            if b > a {
                d += super::ramp_distance(self.kind, a, b, &self.limits(k));
            }
            if hi <= self.top_of(k) {
                break;
            }
        }
        d
    }

    /// Largest v ≥ `v` whose ramp to (`entry`) or from `v` fits in `length`: up through the bands
    /// while each one's whole ramp fits, then the law's own answer in the band where it ends.
    fn max_speed(&self, length: f64, v: f64, entry: bool) -> f64 {
        let law = |rem: f64, u: f64, lim: &Limits| {
            if entry {
                super::max_entry(self.kind, rem, u, lim)
            } else {
                super::max_exit(self.kind, rem, u, lim)
            }
        };
        let (mut rem, mut u) = (length, v.max(0.0));
        let mut k = self.band_of(u);
        // At a band's top the ramp up starts in the band above.
        if k + 1 < self.count() && u >= self.top_of(k) {
            k += 1;
        }
        loop {
            let lim = self.limits(k);
            if k + 1 == self.count() {
                return law(rem, u, &lim);
            }
            let top = self.top_of(k);
            let full = super::ramp_distance(self.kind, u, top, &lim);
            if full > rem {
                return law(rem, u, &lim).min(top);
            }
            rem -= full;
            u = top;
            k += 1;
        }
    }

    /// Largest v_in ≥ v_out from which the bands' ramps slow to `v_out` within `length`.
    pub fn max_entry(&self, length: f64, v_out: f64) -> f64 {
        if self.bands.is_empty() {
            return super::max_entry(self.kind, length, v_out, self.top);
        }
        if self.joined() {
            return scurve7_banded::max_speed(self, length, v_out);
        }
        self.max_speed(length, v_out, true)
    }

    /// Largest v_out ≥ v_in the bands' ramps reach from `v_in` within `length`.
    pub fn max_exit(&self, length: f64, v_in: f64) -> f64 {
        if self.bands.is_empty() {
            return super::max_exit(self.kind, length, v_in, self.top);
        }
        if self.joined() {
            return scurve7_banded::max_speed(self, length, v_in);
        }
        self.max_speed(length, v_in, false)
    }

    /// Largest exit x ≤ `target` whose ramp from `v_in` fits in `length`, when a stop fits (0 if
    /// not): down through the bands above the target's (each whole ramp fits, since the stop
    /// does), then the law's own answer in the target's band. There the distance from the band's
    /// entry speed u is unimodal in the exit and fits at the band's floor, so its crossing below
    /// the target is the law's "lowest exit" from u.
    pub fn lowest_exit(&self, length: f64, v_in: f64, target: f64) -> f64 {
        if self.bands.is_empty() {
            return super::lowest_exit(self.kind, length, v_in, target, self.top);
        }
        if self.joined() {
            return scurve7_banded::lowest_exit(self, length, v_in, target);
        }
        if self.ramp_distance(v_in, target) <= length {
            return target;
        }
        let (mut rem, mut u) = (length, v_in.max(0.0));
        let mut k = self.band_of(u);
        while k > 0 && self.floor_of(k) > target {
            let floor = self.floor_of(k);
            let full = super::ramp_distance(self.kind, u, floor, &self.limits(k));
            if full > rem {
                return 0.0;
            }
            rem -= full;
            u = floor;
            k -= 1;
        }
        super::lowest_exit(self.kind, rem, u, target, &self.limits(k))
    }

    /// The parts a block of `length` runs as, from `v_in` to `v_out` through at most `v_feed`
    /// (speeds the look-ahead found reachable with these bands): ramps up through the bands below
    /// the peak band, the peak band's own block, ramps down. Of the highest peak band whose ramps
    /// fit and the one below it (a peak just inside a band pays that band's whole jerk phases),
    /// the faster one.
    pub fn parts(&self, length: f64, v_in: f64, v_out: f64, v_feed: f64) -> Vec<BandPart> {
        let base = self.band_of(v_in).max(self.band_of(v_out));
        let mut p = base;
        while p + 1 < self.count()
            && v_feed > self.top_of(p)
            && self.ramp_distance(v_in, self.top_of(p)) + self.ramp_distance(self.top_of(p), v_out) <= length
        {
            p += 1;
        }
        let best = self.parts_peaking_in(p, length, v_in, v_out, v_feed);
        if p == base {
            return best;
        }
        let lower = self.parts_peaking_in(p - 1, length, v_in, v_out, v_feed);
        let time = |parts: &[BandPart]| parts.iter().map(|x| x.profile.duration()).sum::<f64>();
        let end = |parts: &[BandPart]| parts.last().map_or(0.0, |x| x.profile.v_end());
        // The lower peak only where it ends as planned too (rounding of the ramps).
        if time(&lower) < time(&best) && end(&lower) <= end(&best) {
            lower
        } else {
            best
        }
    }

    fn parts_peaking_in(&self, p: usize, length: f64, v_in: f64, v_out: f64, v_feed: f64) -> Vec<BandPart> {
        let floor = self.floor_of(p);
        // Speeds at which the parts meet, up from v_in and down to v_out.
        let mut ups: Vec<(f64, f64, usize)> = Vec::new();
        let mut u = v_in.max(0.0);
        for k in self.band_of(u)..p {
            let top = self.top_of(k);
            if top > u {
                ups.push((u, top, k));
                u = top;
            }
        }
        let mut downs: Vec<(f64, f64, usize)> = Vec::new();
        let mut w = v_out.max(0.0);
        for k in self.band_of(w)..p {
            let top = self.top_of(k);
            if top > w {
                downs.push((top, w, k));
                w = top;
            }
        }
        downs.reverse();
        let ramp = |a: f64, b: f64, k: usize| super::ramp_distance(self.kind, a, b, &self.limits(k));
        let ramps: f64 = ups.iter().chain(&downs).map(|&(a, b, k)| ramp(a, b, k)).sum();
        let peak_length = (length - ramps).max(0.0);
        let mut parts = Vec::with_capacity(ups.len() + downs.len() + 1);
        let mut s0 = 0.0;
        let mut v = v_in.max(0.0);
        let mut push = |len: f64, k: usize, v_to: f64, feed: f64, v: &mut f64| {
            let limits = self.limits(k);
            let req = BlockRequest {
                length: len,
                v_in: *v,
                v_out: v_to,
                v_feed: feed.min(limits.v_max),
                limits,
            };
            let profile = Profile::plan(self.kind, &req);
            let v_end = profile.v_end();
            parts.push(BandPart {
                s0,
                length: len,
                limits,
                v_in: *v,
                v_out: v_end,
                v_feed: req.v_feed,
                profile,
            });
            s0 += len;
            *v = v_end;
        };
        for &(a, b, k) in &ups {
            push(ramp(a, b, k), k, b, b, &mut v);
        }
        let peak_out = v_out.max(floor);
        push(peak_length, p, peak_out, v_feed.max(v).max(peak_out), &mut v);
        for &(a, b, k) in &downs {
            push(ramp(a, b, k), k, b, a, &mut v);
        }
        parts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn top() -> Limits {
        Limits {
            v_max: 0.25,
            a_max: 1.0,
            j_max: 1e6,
            snap_max: 1e9,
        }
    }

    fn bands() -> Bands {
        let levels = [
            Band {
                v_top: 0.15,
                a_max: 1.8,
                j_max: 1e6,
            },
            Band {
                v_top: 0.2,
                a_max: 1.5,
                j_max: 1e6,
            },
        ];
        Bands::below(&top(), &levels)
    }

    /// Levels at or above the top speed are dropped; the rest are kept by speed.
    #[test]
    fn below_keeps_the_levels_under_the_top() {
        let t = top();
        let level = |v_top: f64| Band {
            v_top,
            a_max: 1.5,
            j_max: 1e6,
        };
        let b = Bands::below(&t, &[level(0.2), level(0.1), level(0.3), level(0.25), level(0.1)]);
        assert_eq!(b.levels().iter().map(|b| b.v_top).collect::<Vec<_>>(), [0.1, 0.2]);
    }

    /// Band by band (acceleration zero at the edges), the trapezoid's ramp is v²/2A per band.
    #[test]
    fn ramp_distance_adds_the_bands() {
        let (t, b) = (top(), bands());
        let banded = Banded {
            kind: ProfileKind::Trapezoid,
            top: &t,
            bands: &b,
        };
        let d = banded.ramp_distance(0.0, 0.25);
        let expected =
            0.15f64.powi(2) / 3.6 + (0.2f64.powi(2) - 0.15f64.powi(2)) / 3.0 + (0.0625 - 0.04) / 2.0;
        assert!((d - expected).abs() < 1e-15, "{d} vs {expected}");
        assert!((banded.ramp_distance(0.25, 0.0) - d).abs() < 1e-18);
    }

    /// The look-ahead's answers are consistent with the parts: a block planned from max_entry's
    /// speed to v_out ends there, parts meet, lengths add up, no part leaves its band.
    #[test]
    fn parts_reach_what_the_lookahead_promised() {
        let (t, b) = (top(), bands());
        // scurve7 runs across the edges (scurve7_banded.rs, tested there); the others in parts.
        for kind in ProfileKind::ALL
            .into_iter()
            .filter(|k| *k != ProfileKind::Scurve7)
        {
            let banded = Banded {
                kind,
                top: &t,
                bands: &b,
            };
            for &length in &[1e-4, 1e-3, 0.01, 0.03, 0.1] {
                for &v_out in &[0.0, 0.05, 0.17, 0.22] {
                    let v_in = banded.max_entry(length, v_out).min(0.25);
                    let parts = banded.parts(length, v_in, v_out, 0.25);
                    let total: f64 = parts.iter().map(|p| p.length).sum();
                    assert!((total - length).abs() <= 1e-12 * length, "{kind:?} {length}");
                    for w in parts.windows(2) {
                        assert_eq!(w[0].v_out, w[1].v_in);
                        assert!((w[0].s0 + w[0].length - w[1].s0).abs() <= 1e-15);
                    }
                    for p in &parts {
                        assert!(
                            p.v_in <= p.limits.v_max * (1.0 + 1e-12)
                                && p.v_out <= p.limits.v_max * (1.0 + 1e-12)
                        );
                        assert!((p.profile.length() - p.length).abs() <= 1e-9 * length.max(1e-9));
                    }
                    let end = parts.last().unwrap().v_out;
                    assert!(
                        (end - v_out).abs() <= 1e-6 * 0.25,
                        "{kind:?} L {length} v_in {v_in}: ends at {end}, not {v_out}"
                    );
                    let up = banded.max_exit(length, v_out);
                    assert!(
                        (up - v_in).abs() <= 1e-9 || v_in == 0.25,
                        "{kind:?}: max_exit {up} vs max_entry {v_in}"
                    );
                }
            }
        }
    }
}
