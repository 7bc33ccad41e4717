//! Run a scene or deck through the run API, as `junta run INPUT -o DIR -q`
//! does, and print the wall time of `from_file` + `run`: the API side of
//! `bench/api_vs_cli.py`.
//!
//! ```sh
//! cargo run --release -p junta --example run_file -- INPUT DIR
//! ```

use junta::{RunSettings, Simulation};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(input), Some(dir)) = (args.get(1), args.get(2)) else {
        return Err("usage: run_file INPUT DIR".into());
    };
    let t0 = Instant::now();
    let results = Simulation::from_file(input)?.run(&RunSettings::into_dir(dir), &mut [])?;
    println!(
        "{input}: {} in {:.3} s",
        results.status_line,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
