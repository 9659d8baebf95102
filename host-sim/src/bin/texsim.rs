//! `texsim`: render, check and report on texcore scenes from the host.
fn main() {
    std::process::exit(host_sim_main());
}

fn host_sim_main() -> i32 {
    eprintln!("texsim: no commands yet");
    2
}
