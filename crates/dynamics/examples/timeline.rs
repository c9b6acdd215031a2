//! Prints the segments of the default O-A-B-C-O path: `cargo run --example timeline`.
use navkf_dynamics::{Trajectory, TrajectoryConfig};
fn main() {
    let traj = Trajectory::build(&TrajectoryConfig::default()).expect("default path builds");
    for s in traj.segments() {
        println!(
            "{:8.1} s  {:7.1} s  {:7}  {:?}",
            s.start,
            s.duration,
            s.label,
            s.phase()
        );
    }
}
