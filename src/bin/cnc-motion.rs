//! `cnc-motion` command line: profile, run, package.
fn main() {
    eprintln!("cnc-motion: not yet wired");
    std::process::exit(2);
}
