//! ns per single-block profile, general case (V_in ≠ 0, V_out ≠ 0, cruise not reached), per law.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::feed::{BlockRequest, FeedLaw, Limits, Profile, ProfileKind};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let limits = Limits {
        v_max: 0.5,
        a_max: 9.8,
        j_max: 40.0,
        snap_max: 6000.0,
    };
    // Seed 004's appendix block: V_in 0.2, V_out 0.1, V_F 0.5 m/s on 0.1 m (peak speed solved).
    let general = BlockRequest {
        length: 0.1,
        v_in: 0.2,
        v_out: 0.1,
        v_feed: 0.5,
        limits,
    };
    let mut g = c.benchmark_group("profile");
    for kind in ProfileKind::ALL {
        g.bench_with_input(
            BenchmarkId::new("general_block", kind.name()),
            &general,
            |b, req| b.iter(|| Profile::plan(kind, black_box(req)).duration()),
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
