//! Geometry kernel benchmarks (filled in as the kernel lands).
fn main() {}
