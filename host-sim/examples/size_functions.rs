//! Prints texcore's `.text` per function of a firmware ELF (largest first).
fn main() {
    let path = std::env::args().nth(1).expect("ELF path");
    let facts = host_sim::report::size::analyse(std::path::Path::new(&path)).expect("analyse");
    let mut v: Vec<_> = facts.texcore_by_function.iter().collect();
    v.sort_by(|a, b| b.1.cmp(a.1));
    let total: u64 = v.iter().map(|x| *x.1).sum();
    println!("texcore .text {total}");
    for (f, b) in v.iter().take(
        std::env::args()
            .nth(2)
            .and_then(|n| n.parse().ok())
            .unwrap_or(60),
    ) {
        println!("{b:6} {f}");
    }
}
