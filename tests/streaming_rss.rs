//! Issue 11: the CLI streams the program, so its peak memory does not grow with the program's
//! length (it was about twice the file size). Alone in its test binary: getrusage(CHILDREN) is
//! the peak of every child this process waited for.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use std::io::Write;
use std::process::Command;

/// Peak resident set of the waited-for children (bytes; Linux reports KiB).
fn children_peak_rss() -> u64 {
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: getrusage writes one rusage struct, which `usage` is.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    assert_eq!(rc, 0);
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn peak_memory_does_not_grow_with_program_length() {
    let dir = std::env::temp_dir().join(format!("cnc-rss-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("long.ngc");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    writeln!(f, "G21 G90 G61 G1 F6000").unwrap();
    // 60 MB: 300 moves (exact stop), each followed by 2 000 comment lines of 100 bytes.
    let comment = format!("({})", "c".repeat(97));
    for k in 0..300 {
        writeln!(f, "X{}", k % 2 + 1).unwrap();
        for _ in 0..2000 {
            writeln!(f, "{comment}").unwrap();
        }
    }
    writeln!(f, "M30").unwrap();
    drop(f);
    let size = std::fs::metadata(&path).unwrap().len();
    let out = Command::new(env!("CARGO_BIN_EXE_cnc-motion"))
        .args(["run", path.to_str().unwrap(), "--json", "--max-time", "600"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(summary["motion_blocks"], 300);
    let peak = children_peak_rss();
    eprintln!(
        "program {} MB, CLI peak RSS {} MB",
        size / 1_000_000,
        peak / 1_000_000
    );
    assert!(size > 60_000_000);
    // A whole-text reader needs at least the file size; streaming stays at a small fixed amount.
    assert!(peak < size / 4, "peak RSS {peak} bytes for a {size}-byte program");
    std::fs::remove_dir_all(&dir).ok();
}
