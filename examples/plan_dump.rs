//! Print the planned segments of a program: line, kind, length, v_in, v_out, duration.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::config::Machine;
use cnc_motion::feed::FeedLaw;
use cnc_motion::gcode::Reader;
use cnc_motion::path::{PathBuilder, Segment};
use cnc_motion::plan::Planner;
use std::collections::VecDeque;
use std::sync::Arc;

/// With PATH_DUMP set: the path block's limits and speed bands (mm, s).
fn describe(b: &cnc_motion::path::PathBlock) {
    if std::env::var_os("PATH_DUMP").is_none() {
        return;
    }
    let l = &b.limits;
    print!(
        "  path {:4} L={:9.4} v_max={:8.3} a={:8.1} j={:10.1} v_end_max={:8.3} bands:",
        b.line,
        b.segment.length() * 1e3,
        l.v_max * 1e3,
        l.a_max * 1e3,
        l.j_max * 1e3,
        b.v_end_max * 1e3
    );
    for band in b.bands.levels() {
        print!(
            " [{:.3} {:.1} {:.1}]",
            band.v_top * 1e3,
            band.a_max * 1e3,
            band.j_max * 1e3
        );
    }
    if let Segment::Chain(c) = &b.segment {
        print!(" pieces:");
        for p in &c.pieces {
            let kind = match p.curve {
                cnc_motion::path::Curve::Line(_) => "line",
                cnc_motion::path::Curve::Arc(_) => "arc",
                cnc_motion::path::Curve::Hermite(_) => "herm",
            };
            print!(" {kind}:{:.4}", p.length() * 1e3);
        }
    }
    println!();
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).expect("program");
    let machine = match args.get(2) {
        Some(p) => Machine::from_toml(&std::fs::read_to_string(p).expect("machine"), p).expect("machine"),
        None => Machine::default(),
    };
    let mut reader = Reader::new(Arc::from(text), &args[1], [0.0; 3]);
    let mut builder = PathBuilder::new(&machine);
    let mut planner = Planner::new(machine.profile, machine.lookahead_blocks);
    let (mut segs, mut out) = (Vec::new(), VecDeque::new());
    while let Some(b) = reader.next_block().expect("valid") {
        builder.push(&b, &mut segs);
        for s in segs.drain(..) {
            describe(&s);
            planner.push(s, &mut out);
        }
    }
    builder.finish(&mut segs);
    for s in &segs {
        describe(s);
    }
    for s in segs.drain(..) {
        planner.push(s, &mut out);
    }
    planner.finish(&mut out);
    let mut total = 0.0;
    for p in &out {
        let kind = match p.block.segment {
            Segment::Line(_) => "line",
            Segment::Arc(_) => "arc",
            Segment::Blend(_) => "blend",
            Segment::Dwell { .. } => "dwell",
            Segment::Part { .. } => "part",
            Segment::Chain(ref c) => {
                print!("[{} pieces] ", c.pieces.len());
                "chain"
            }
        };
        total += p.profile.duration();
        println!(
            "{:4} {:6} L={:9.4} mm  v_in={:8.3}  v_out={:8.3}  feed={:8.3} mm/s  T={:.4} s  (t={:.4})",
            p.block.line,
            kind,
            p.block.segment.length() * 1e3,
            p.v_in * 1e3,
            p.v_out * 1e3,
            p.block.v_feed * 1e3,
            p.profile.duration(),
            total
        );
    }
}
