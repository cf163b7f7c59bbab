//! Tests of the banded S-curve: equal bands are scurve7, blocks keep each band's limits, the
//! planning questions invert the ramp distance.

use super::*;
use crate::feed::bands::{Band, Bands};
use crate::feed::{scurve7, BlockRequest, Limits, ProfileKind};
use crate::test_rng::unit;

fn limits(v_max: f64, a_max: f64, j_max: f64) -> Limits {
    Limits {
        v_max,
        a_max,
        j_max,
        snap_max: 1e9,
    }
}

fn band(v_top: f64, a_max: f64, j_max: f64) -> Band {
    Band { v_top, a_max, j_max }
}

/// Bands whose limits are all the same are no bands: ramps, entries, exits and blocks equal
/// scurve7's closed forms (the 7-phase law, which equals Ruckig rest to rest).
#[test]
fn equal_bands_are_scurve7() {
    let top = limits(0.3, 2.0, 50.0);
    let bands = Bands::below(
        &top,
        &[band(0.05, 2.0, 50.0), band(0.12, 2.0, 50.0), band(0.2, 2.0, 50.0)],
    );
    let b = Banded {
        kind: ProfileKind::Scurve7,
        top: &top,
        bands: &bands,
    };
    for (v1, v2) in [(0.0, 0.3), (0.02, 0.17), (0.1, 0.11), (0.0, 0.01), (0.25, 0.3)] {
        let ours = ramp_distance(&b, v1, v2);
        let theirs = scurve7::ramp_distance(v1, v2, &top);
        assert!(
            (ours - theirs).abs() <= 1e-12 * theirs,
            "{v1} → {v2}: {ours} vs {theirs}"
        );
    }
    for (length, v_in, v_out) in [
        (0.05, 0.0, 0.0),
        (0.002, 0.0, 0.0),
        (0.01, 0.1, 0.02),
        (0.3, 0.05, 0.0),
    ] {
        let ours = plan(&b, length, v_in, v_out, 0.3);
        let theirs = scurve7::plan(&BlockRequest {
            length,
            v_in,
            v_out,
            v_feed: 0.3,
            limits: top,
        });
        assert!(
            (ours.duration() - theirs.duration()).abs() <= 1e-9 * theirs.duration(),
            "L {length}"
        );
        assert!((ours.length() - length).abs() <= 1e-12 * length);
        assert!((ours.v_end() - theirs.v_end()).abs() <= 1e-9);
    }
    let (l, v) = (0.004, 0.03);
    assert!((max_speed(&b, l, v) - scurve7::max_entry(l, v, &top)).abs() <= 1e-12);
}

fn falling_bands() -> (Limits, Bands) {
    let top = limits(0.25, 0.4, 20.0);
    let bands = Bands::below(
        &top,
        &[
            band(0.08, 2.0, 60.0),
            band(0.15, 1.5, 45.0),
            band(0.2, 0.9, 30.0),
            band(0.23, 0.6, 400.0),
        ],
    );
    (top, bands)
}

/// Bands whose acceleration rises and falls with speed (a middle band allows more).
fn mixed_bands() -> (Limits, Bands) {
    let top = limits(0.25, 0.5, 30.0);
    let bands = Bands::below(
        &top,
        &[
            band(0.05, 0.8, 80.0),
            band(0.12, 1.9, 40.0),
            band(0.18, 0.7, 300.0),
            band(0.22, 1.1, 20.0),
        ],
    );
    (top, bands)
}

/// The band of speed v: its acceleration and jerk.
fn band_limits(b: &Banded, v: f64) -> (f64, f64) {
    for k in 0..b.count() {
        let l = b.limits(k);
        if v <= b.top_of(k) {
            return (l.a_max, l.j_max);
        }
    }
    unreachable!()
}

/// Blocks across falling bands, sampled finely: speed, acceleration and jerk within the band
/// of the speed at every instant, continuous acceleration, the length and the exit as asked,
/// and never slower than ramping band by band with the acceleration zero at each edge.
#[test]
fn blocks_keep_each_bands_limits() {
    for (top, bands) in [falling_bands(), mixed_bands()] {
        blocks_within(&top, &bands);
    }
}

fn blocks_within(top: &Limits, bands: &Bands) {
    let b = Banded {
        kind: ProfileKind::Scurve7,
        top,
        bands,
    };
    let by_parts = Banded {
        kind: ProfileKind::Quintic,
        ..b
    };
    for &length in &[1e-4, 1e-3, 0.01, 0.05, 0.3] {
        for &v_out in &[0.0, 0.1, 0.21, 0.24] {
            let v_in = max_speed(&b, length, v_out).min(0.25);
            let p = plan(&b, length, v_in, v_out, 0.25);
            assert!(
                (p.length() - length).abs() <= 1e-12 * length.max(1e-3),
                "L {length}: {}",
                p.length()
            );
            assert!(
                (p.v_end() - v_out).abs() <= 1e-9,
                "ends at {} not {v_out}",
                p.v_end()
            );
            let n = 4000;
            let mut last_a = 0.0;
            for i in 0..=n {
                let k = p.at(p.duration() * i as f64 / n as f64);
                let (a_max, j_max) = band_limits(&b, k.v);
                assert!(k.v <= 0.25 * (1.0 + 1e-12) && k.v >= -1e-12);
                assert!(
                    k.a.abs() <= a_max * (1.0 + 1e-9) + 1e-12,
                    "a {} > {a_max} at v {}",
                    k.a,
                    k.v
                );
                assert!(
                    k.j.abs() <= j_max * (1.0 + 1e-9),
                    "j {} > {j_max} at v {}",
                    k.j,
                    k.v
                );
                assert!(
                    (k.a - last_a).abs() <= 400.0 * p.duration() / n as f64 * 1.01 + 1e-12,
                    "a jumps {last_a} → {} at v {} (L {length}, v_in {v_in}, v_out {v_out}): {:?}",
                    k.a,
                    k.v,
                    p.phases
                );
                last_a = k.a;
            }
            // Rest to rest against the band-by-band parts of the same bands with scurve7's ramps.
            let ours = plan(&b, length, 0.0, 0.0, 0.25).duration();
            let parts: f64 = Banded {
                kind: ProfileKind::Scurve7,
                ..by_parts
            }
            .parts(length, 0.0, 0.0, 0.25)
            .iter()
            .map(|p| p.profile.duration())
            .sum();
            assert!(
                ours <= parts * (1.0 + 1e-9),
                "L {length}: {ours} vs parts {parts}"
            );
        }
    }
}

/// A drop is the rise reversed: the same distance both ways, and the largest entry, the
/// largest exit and the lowest exit agree with the distance they invert.
#[test]
fn planning_questions_invert_the_distance() {
    let (top, bands) = falling_bands();
    let b = Banded {
        kind: ProfileKind::Scurve7,
        top: &top,
        bands: &bands,
    };
    for &(length, v) in &[(1e-3, 0.0), (0.01, 0.05), (0.02, 0.19), (0.2, 0.0)] {
        let w = max_speed(&b, length, v);
        assert!(ramp_distance(&b, v, w) <= length);
        assert!(ramp_distance(&b, v, w * (1.0 + 1e-9) + 1e-15) > length);
        assert_eq!(ramp_distance(&b, v, w), ramp_distance(&b, w, v));
    }
    for &(v_in, length, target) in &[(0.24, 0.03, 0.2), (0.24, 0.002, 0.1), (0.24, 0.0005, 0.2)] {
        let x = lowest_exit(&b, length, v_in, target);
        assert!(x <= target);
        if ramp_distance(&b, v_in, target) <= length {
            assert_eq!(x, target);
        } else if ramp_distance(&b, v_in, 0.0) <= length {
            assert!(ramp_distance(&b, v_in, x) <= length);
            assert!(
                x == target || ramp_distance(&b, v_in, x + 1e-9) > length,
                "{x} is not the largest"
            );
        } else {
            assert_eq!(x, 0.0);
        }
    }
}

/// Every answer is the crossing of the ramp distance as evaluated, whether scurve7's closed
/// form in one band gave it (`crossing_near`) or the regula falsi: on 200 random band sets, the
/// largest speed, the lowest exit and a block's peak fit, and 1.5 `ROOT_TOL` more does not (the
/// exit: 1e-9 of the target more, where the drop's distance is flat to rounding). `plan_time`
/// is the block's duration and peak bit for bit; the largest speed's search given up outside a
/// range is so only where the speed is outside it, and is that speed bit for bit elsewhere.
#[test]
fn answers_are_crossings_within_the_tolerance() {
    use crate::feed::tolerance::ROOT_TOL;
    let mut s = 0x2545_f491_4f6c_dd1du64;
    let over = |x: f64| x * (1.0 + 1.5 * ROOT_TOL) + 1e-300;
    let (mut exits, mut peaks) = (0, 0);
    for _ in 0..200 {
        let top = limits(
            0.1 + 0.3 * unit(&mut s),
            0.2 + 2.0 * unit(&mut s),
            5.0 + 500.0 * unit(&mut s),
        );
        let n = (unit(&mut s) * 17.0) as usize;
        let levels: Vec<Band> = (0..n)
            .map(|k| {
                let v = top.v_max * (k as f64 + unit(&mut s)) / n as f64;
                band(v, 0.3 + 3.0 * unit(&mut s), 5.0 + 600.0 * unit(&mut s))
            })
            .collect();
        let bands = Bands::below(&top, &levels);
        let b = Banded {
            kind: ProfileKind::Scurve7,
            top: &top,
            bands: &bands,
        };
        for _ in 0..10 {
            let (v0, length) = (top.v_max * unit(&mut s), 1e-3 * 100f64.powf(unit(&mut s)) / 10.0);
            let w = max_speed(&b, length, v0);
            assert!(ramp_distance(&b, v0, w) <= length);
            assert!(ramp_distance(&b, v0, over(w)) > length, "{v0} {length}: {w}");
            // Given up outside a range only where the answer is outside it; else the answer.
            let rise = Rise::from(&b, v0);
            for v in [0.5 * w, w, over(w), 2.0 * w] {
                match rise.max_speed_within(length, (v, f64::INFINITY)) {
                    Some(x) => assert_eq!(x.to_bits(), w.to_bits(), "{v0} {length} {v}"),
                    None => assert!(w < v, "{v0} {length}: {w} given up below {v}"),
                }
                match rise.max_speed_within(length, (f64::NEG_INFINITY, v)) {
                    Some(x) => assert_eq!(x.to_bits(), w.to_bits(), "{v0} {length} {v}"),
                    None => assert!(w >= v, "{v0} {length}: {w} given up above {v}"),
                }
            }
            // A drop that ends inside (0, target): a stop fits, the drop to the target not.
            let target = v0 * (0.1 + 0.4 * unit(&mut s));
            let (d_stop, d_target) = (ramp_distance(&b, v0, 0.0), ramp_distance(&b, v0, target));
            let room = d_stop + (d_target - d_stop) * unit(&mut s);
            let x = lowest_exit(&b, room, v0, target);
            if x > 0.0 && x < target {
                let length = room;
                // Near 0 the drop's distance is flat to rounding over ROOT_TOL of x.
                let above = x + 1e-9 * target;
                assert!(ramp_distance(&b, v0, x) <= length && ramp_distance(&b, v0, above) > length);
                exits += 1;
            }
            let (v_in, v_out) = (top.v_max * unit(&mut s), top.v_max * unit(&mut s));
            let p = plan(&b, length, v_in, v_out, top.v_max);
            // Its time alone is the same, bit for bit (equal ends too).
            for (v_in, v_out) in [(v_in, v_out), (v_in, v_in)] {
                let p = plan(&b, length, v_in, v_out, top.v_max);
                let (t, v) = plan_time(&b, length, v_in, v_out, top.v_max);
                assert_eq!(
                    [t, v].map(f64::to_bits),
                    [p.duration(), p.v_peak()].map(f64::to_bits)
                );
            }
            let peak = p.v_peak();
            let total = |v: f64| ramp_distance(&b, v_in, v) + ramp_distance(&b, v, v_out);
            if peak > v_in.max(v_out) && peak < top.v_max {
                assert!(
                    total(peak) <= length * (1.0 + 1e-12) && total(over(peak)) > length,
                    "peak {peak}"
                );
                peaks += 1;
            }
        }
    }
    assert!(
        exits > 100 && peaks > 100,
        "too few cases: {exits} exits, {peaks} peaks"
    );
}
