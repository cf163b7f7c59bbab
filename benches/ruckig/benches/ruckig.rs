//! One rest-to-rest block, S-curve (scurve7), against Ruckig's 1-DoF time-optimal profile
//! (position control, the same v/a/j limits, rest at both ends), in the same run. 64 blocks from
//! 0.05 mm to 20 mm at F3000–F6000 (cruise reached and not), cycled so that no branch is
//! learned; both sides are checked to give the same duration first.

use cnc_motion::feed::{BlockRequest, FeedLaw, Limits, Profile, ProfileKind};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

/// (length m, v_max m/s, a_max m/s², j_max m/s³)
fn blocks() -> Vec<(f64, f64, f64, f64)> {
    // A fixed LCG: the same blocks every run.
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut unit = || {
        x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..64)
        .map(|_| {
            let length = 5e-5 * (400.0f64).powf(unit());
            let v_max = 0.05 + 0.05 * unit();
            let a_max = 1.0 + 2.0 * unit();
            let j_max = 20.0 + 80.0 * unit();
            (length, v_max, a_max, j_max)
        })
        .collect()
}

fn request(&(length, v_max, a_max, j_max): &(f64, f64, f64, f64)) -> BlockRequest {
    BlockRequest {
        length,
        v_in: 0.0,
        v_out: 0.0,
        v_feed: v_max,
        limits: Limits {
            v_max,
            a_max,
            j_max,
            snap_max: 1e3 * j_max,
        },
    }
}

struct Ruckig {
    otg: ruckig::Ruckig,
    input: ruckig::InputParameter,
    trajectory: ruckig::Trajectory,
}

impl Ruckig {
    fn new() -> Ruckig {
        let mut input = ruckig::InputParameter::new(1);
        input.current_position = vec![0.0];
        input.current_velocity = vec![0.0];
        input.current_acceleration = vec![0.0];
        input.target_velocity = vec![0.0];
        input.target_acceleration = vec![0.0];
        input.target_position = vec![0.0];
        input.max_velocity = vec![1.0];
        input.max_acceleration = vec![1.0];
        input.max_jerk = vec![1.0];
        Ruckig {
            otg: ruckig::Ruckig::new_direct_and_offline(1),
            input,
            trajectory: ruckig::Trajectory::new_direct(1),
        }
    }

    /// The block's duration (s).
    fn plan(&mut self, &(length, v_max, a_max, j_max): &(f64, f64, f64, f64)) -> f64 {
        // In place: no allocation on our side of the wrapper.
        self.input.target_position[0] = length;
        self.input.max_velocity[0] = v_max;
        self.input.max_acceleration[0] = a_max;
        self.input.max_jerk[0] = j_max;
        let r = self.otg.calculate(&mut self.input, &mut self.trajectory);
        assert!(r == ruckig::Result::Working || r == ruckig::Result::Finished);
        self.trajectory.get_duration()
    }
}

fn bench(c: &mut Criterion) {
    let blocks = blocks();
    let mut r = Ruckig::new();
    for b in &blocks {
        let ours = Profile::plan(ProfileKind::Scurve7, &request(b)).duration();
        let theirs = r.plan(b);
        assert!(
            (ours - theirs).abs() <= 1e-9 * theirs,
            "{b:?}: scurve7 {ours} s, Ruckig {theirs} s"
        );
    }
    let requests: Vec<BlockRequest> = blocks.iter().map(request).collect();
    let mut g = c.benchmark_group("rest_to_rest_64_blocks");
    g.bench_function("scurve7", |b| {
        b.iter(|| {
            requests
                .iter()
                .map(|q| Profile::plan(ProfileKind::Scurve7, black_box(q)).duration())
                .sum::<f64>()
        })
    });
    g.bench_function("ruckig", |b| {
        b.iter(|| blocks.iter().map(|q| r.plan(black_box(q))).sum::<f64>())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
