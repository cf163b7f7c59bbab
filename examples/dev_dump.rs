//! Densely sample each planned piece and print its worst distance to the given program points
//! (debugging aid for tolerance checks; the geometry must be passed as the test builds it).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::config::Machine;
use cnc_motion::gcode::{Motion, Reader};
use cnc_motion::path::{Arc as ArcGeo, Line, PathBuilder, Source};
use std::sync::Arc;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).expect("program");
    let machine = Machine::default();
    let mut reader = Reader::new(Arc::from(text), &args[1], [0.0; 3]);
    let mut builder = PathBuilder::new(&machine);
    let (mut segs, mut geo) = (Vec::new(), Vec::new());
    while let Some(b) = reader.next_block().expect("valid") {
        match b.motion {
            Motion::Linear { to } => geo.push(Source::Line(Line {
                start: b.from,
                end: to,
            })),
            Motion::Arc {
                to,
                center,
                plane,
                clockwise,
                turns,
            } => geo.push(Source::Arc(
                ArcGeo::from_gcode(b.from, to, center, plane, clockwise, turns).unwrap(),
            )),
            _ => {}
        }
        builder.push(&b, &mut segs);
    }
    builder.finish(&mut segs);
    for s in &segs {
        let n = 20000;
        let mut worst: f64 = 0.0;
        for k in 0..=n {
            let p = s.segment.eval(s.segment.length() * k as f64 / n as f64).p;
            let d = geo.iter().map(|g| g.distance(p)).fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        println!(
            "line {} len {:.5} mm worst {:.6} mm",
            s.line,
            s.segment.length() * 1e3,
            worst * 1e3
        );
    }
}
