//! Writes a CAM-like program (benches/common/cam_like.rs) for throughput and memory runs of the
//! CLI: `cargo run --release --example cam_program -- MOVES FILE [SEED]`, e.g.
//! `… -- 1000000 /tmp/cam_1m.ngc` then `cnc-motion run /tmp/cam_1m.ngc --json`.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[allow(dead_code)]
#[path = "../benches/common/cam_like.rs"]
mod cam_like;

use std::io::Write;

/// `fmt::Write` onto a buffered file: the program is streamed, never held whole.
struct Stream(std::io::BufWriter<std::fs::File>, Option<std::io::Error>);

impl std::fmt::Write for Stream {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.write_all(s.as_bytes()).map_err(|e| {
            self.1 = Some(e);
            std::fmt::Error
        })
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(moves), Some(path)) = (args.first(), args.get(1)) else {
        return Err("usage: cam_program MOVES FILE [SEED]".into());
    };
    let moves: usize = moves.parse()?;
    let seed: u64 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let mut out = Stream(std::io::BufWriter::new(std::fs::File::create(path)?), None);
    if cam_like::write(&mut out, moves, seed).is_err() {
        return Err(format!(
            "{path}: {}",
            out.1.map_or("write failed".into(), |e| e.to_string())
        )
        .into());
    }
    out.0.flush()?;
    Ok(())
}
