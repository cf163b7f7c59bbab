//! Planning and evaluating one general block (v_in, v_out ≠ 0, too short for the feed) per law.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::feed::{BlockRequest, FeedLaw, Limits, Profile, ProfileKind};
use criterion::{black_box, criterion_group, criterion_main, Criterion};

fn general_block() -> BlockRequest {
    BlockRequest {
        length: 0.004,
        v_in: 0.04,
        v_out: 0.01,
        v_feed: 0.2,
        limits: Limits {
            v_max: 0.8,
            a_max: 2.0,
            j_max: 60.0,
            snap_max: 6000.0,
        },
    }
}

fn bench(c: &mut Criterion) {
    let req = general_block();
    for kind in [ProfileKind::Quintic, ProfileKind::Jerk15, ProfileKind::Mixed57] {
        c.bench_function(&format!("{} general block", kind.name()), |b| {
            b.iter(|| Profile::plan(kind, black_box(&req)))
        });
        let p = Profile::plan(kind, &req);
        let t = p.duration();
        c.bench_function(&format!("{} at(t)", kind.name()), |b| {
            b.iter(|| p.at(black_box(0.37 * t)))
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
