//! Print the chains of a program: pieces, derivative bounds and limits (debugging aid).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::config::Machine;
use cnc_motion::gcode::Reader;
use cnc_motion::path::{Curve, PathBuilder, Segment};
use std::sync::Arc;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).expect("program");
    let machine = match args.get(2) {
        Some(p) => Machine::from_toml(&std::fs::read_to_string(p).expect("machine"), p).expect("machine"),
        None => Machine::default(),
    };
    let mut reader = Reader::new(Arc::from(text), &args[1], [0.0; 3]);
    let mut builder = PathBuilder::new(&machine);
    let mut segs = Vec::new();
    while let Some(b) = reader.next_block().expect("valid") {
        builder.push(&b, &mut segs);
    }
    builder.finish(&mut segs);
    for s in segs
        .iter()
        .skip(std::env::var("SKIP").map(|v| v.parse().unwrap()).unwrap_or(0))
        .take(12)
    {
        println!(
            "line {} len {:.5} mm feed {:.3} limits v {:.3} a {:.1} j {:.0} end_max {:.3}",
            s.line,
            s.segment.length() * 1e3,
            s.v_feed * 1e3,
            s.limits.v_max * 1e3,
            s.limits.a_max * 1e3,
            s.limits.j_max * 1e3,
            s.v_end_max * 1e3
        );
        if let Segment::Chain(c) = &s.segment {
            for p in c.pieces.iter().take(4) {
                let kind = match p.curve {
                    Curve::Line(_) => "line",
                    Curve::Arc(_) => "arc",
                    Curve::Hermite(_) => "hermite",
                };
                let b = p.curve.derivative_bounds();
                println!(
                    "   {kind} u {:.5}..{:.5} mm b1 {:?} b2 {:?} b3 {:?}",
                    p.u0 * 1e3,
                    p.u1 * 1e3,
                    b[0],
                    b[1],
                    b[2]
                );
            }
        }
    }
}
