//! Reads `distance,v,a,j` lines from stdin and prints the rest-to-rest duration of Talas's
//! jerk-limited profile for each; a line `distance,v,a,j,v0,v1` gives the duration between the
//! boundary speeds `v0` and `v1` (at zero acceleration) instead, printed to full precision
//! (used by benches/feed_ruckig.py).

use std::io::BufRead as _;

use talas::feed::{Limits1, Profile};

fn main() {
    for line in std::io::stdin().lock().lines().map_while(Result::ok) {
        let v: Vec<f64> = line
            .split(',')
            .filter_map(|x| x.trim().parse().ok())
            .collect();
        if let [s, vel, acc, jerk] = v.as_slice() {
            let lim = Limits1 {
                velocity: *vel,
                acceleration: *acc,
                jerk: *jerk,
            };
            match Profile::rest_to_rest(*s, &lim) {
                Ok(p) => println!("{:.12}", p.duration_s()),
                Err(e) => println!("error {e}"),
            }
        } else if let [s, vel, acc, jerk, v0, v1] = v.as_slice() {
            let lim = Limits1 {
                velocity: *vel,
                acceleration: *acc,
                jerk: *jerk,
            };
            match Profile::calculate(*s, *v0, *v1, &lim) {
                Ok(p) => println!("{:e}", p.duration_s()),
                Err(e) => println!("error {e}"),
            }
        }
    }
}
