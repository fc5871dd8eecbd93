//! `N` calls of one generated function on the benchmark states (`dynamics_tests::bench`), for
//! instruction counts under callgrind: `bench/run.sh` with `CALLGRIND=1` runs it at two values
//! of `N` and divides the difference of the counts by the difference of the calls, so that
//! start-up and the states' set-up cancel.
//!
//! ```text
//! cargo run --release -p dynamics-tests --example calls -- ur5 inverse_dynamics 1000
//! ```
//!
//! With `--time R` after `N` it times them too: `R` rounds of the `N` calls after one round
//! untimed, and prints the median ns per call (`bench/run.sh` interleaves these runs with
//! Pinocchio's benchmark, table 3b). Each call goes through a `&dyn Fn` and one entry of its
//! result is summed: a nanosecond or two per call more than criterion's loop.
//!
//! Functions are named as Pinocchio's benchmark names its algorithms: `rnea`
//! (`inverse_dynamics`), `nle` (`coriolis`, c + g), `crba` (`mass_matrix`), `gravity`, `aba`
//! (`forward_dynamics`), and, for the robots generated with them, `rnea_derivatives`
//! (`inverse_dynamics_derivatives`), `aba_derivatives` (`forward_dynamics_with_derivatives`),
//! `minverse` (`mass_matrix_inverse`) and `gravity_derivatives` (`gravity_derivative`).

use dynamics_tests::bench::{keep, states, STATES};
use std::hint::black_box;
use std::process::ExitCode;

/// Calls `function` of module `$m` `n` times, cycling through the states, `rounds` times, each
/// round timed (ns per call, in `times`); `None` if it has no function of that name. Each whole
/// result goes through [`keep`].
macro_rules! run {
    ($m:ident, $nq:literal, $nv:literal, $function:expr, $n:expr, $rounds:expr, $times:expr, $($derivatives:tt)?) => {{
        use dynamics_tests::generated::$m::Robot as Gen;
        let states = states::<$nq, $nv>(|q, qd, qdd| Gen.inverse_dynamics(q, qd, qdd));
        let mut sum = 0.0;
        let times: &mut Vec<f64> = $times;
        let mut each = |f: &dyn Fn(&dynamics_tests::bench::State<$nq, $nv>) -> f64| {
            for _ in 0..$rounds {
                let start = std::time::Instant::now();
                for i in 0..$n {
                    sum += f(black_box(&states[i & (STATES - 1)]));
                }
                times.push(start.elapsed().as_nanos() as f64 / $n.max(1) as f64);
            }
        };
        let found = match $function {
            "rnea" => { each(&|s| { let r = Gen.inverse_dynamics(&s.q, &s.qd, &s.qdd); keep(&r); r[0] }); true }
            "nle" => { each(&|s| { let r = Gen.coriolis(&s.q, &s.qd); keep(&r); r[0] }); true }
            "crba" => { each(&|s| { let r = Gen.mass_matrix(&s.q); keep(&r); r[(0, $nv - 1)] }); true }
            "gravity" => { each(&|s| { let r = Gen.gravity(&s.q); keep(&r); r[0] }); true }
            "aba" => { each(&|s| { let r = Gen.forward_dynamics(&s.q, &s.qd, &s.tau); keep(&r); r[0] }); true }
            $(
            // (`$derivatives` only marks the robots generated with the derivative functions.)
            "rnea_derivatives" if !stringify!($derivatives).is_empty() => {
                each(&|s| {
                    let r = Gen.inverse_dynamics_derivatives(&s.q, &s.qd, &s.qdd);
                    keep(&r);
                    let (dq, dv) = r;
                    dq[($nv - 1, 0)] + dv[($nv - 1, 0)]
                });
                true
            }
            "aba_derivatives" => {
                each(&|s| {
                    let r = Gen.forward_dynamics_with_derivatives(&s.q, &s.qd, &s.tau);
                    keep(&r);
                    let (a, dq, dv, _) = r;
                    a[0] + dq[($nv - 1, 0)] + dv[($nv - 1, 0)]
                });
                true
            }
            "minverse" => { each(&|s| { let r = Gen.mass_matrix_inverse(&s.q); keep(&r); r[(0, $nv - 1)] }); true }
            "gravity_derivatives" => { each(&|s| { let r = Gen.gravity_derivative(&s.q); keep(&r); r[($nv - 1, 0)] }); true }
            )?
            _ => false,
        };
        found.then_some(sum)
    }};
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (robot, function, n, timed) = match args.as_slice() {
        [robot, function, n] => (robot, function, n, None),
        [robot, function, n, flag, r] if flag == "--time" => (robot, function, n, Some(r)),
        _ => {
            eprintln!(
                "usage: calls ROBOT FUNCTION N [--time R] (robots: ur5 panda rand7 talos_upper_body solo12 g1_29dof)"
            );
            return ExitCode::from(2);
        }
    };
    let Ok(n) = n.parse::<usize>() else {
        eprintln!("N must be a number of calls, not {n:?}");
        return ExitCode::from(2);
    };
    let rounds = match timed.map(|r| r.parse::<usize>()) {
        None => 1,
        Some(Ok(r)) if r > 0 => r + 1,
        Some(_) => {
            eprintln!("--time takes a number of rounds (at least 1)");
            return ExitCode::from(2);
        }
    };
    let f = function.as_str();
    let mut times = Vec::with_capacity(rounds);
    let t = &mut times;
    let sum = match robot.as_str() {
        "ur5" => run!(urdf_ur5, 6, 6, f, n, rounds, t, derivatives),
        "panda" => run!(urdf_panda, 7, 7, f, n, rounds, t, derivatives),
        "rand7" => run!(urdf_rand7, 7, 7, f, n, rounds, t, derivatives),
        "solo12" => run!(tree_solo12, 19, 18, f, n, rounds, t, derivatives),
        "talos_upper_body" => run!(tree_talos_upper_body, 20, 20, f, n, rounds, t,),
        "g1_29dof" => run!(tree_g1_29dof, 36, 35, f, n, rounds, t,),
        other => {
            eprintln!("no robot {other:?} (ur5 panda rand7 talos_upper_body solo12 g1_29dof)");
            return ExitCode::from(2);
        }
    };
    match sum {
        Some(sum) if timed.is_some() => {
            // The first round is the warm-up.
            let mut timed = times.split_off(1);
            timed.sort_by(f64::total_cmp);
            println!("{robot} {function} {:.1}", timed[timed.len() / 2]);
            black_box(sum);
            ExitCode::SUCCESS
        }
        Some(sum) => {
            println!("{robot} {function} {n} calls (sum {sum:.3e})");
            ExitCode::SUCCESS
        }
        None => {
            eprintln!("{robot} has no function {function:?} here");
            ExitCode::from(2)
        }
    }
}
