//! Split passes against the one-thread pass they stand for: on many random contacts
//! among many bodies (wide levels), a helper thread taking chunks of each level beside
//! the leader must leave every velocity bit for bit as the plain pass does.

use super::split::{self, Runner};
use super::wide_tests::{assert_same, random_body, random_contact};
use super::{Pass, solve_steps, warm_start_steps};
use crate::rng::Rnd;
use crate::world::{ContactBatches, ContactConstraint, SolverBody};

#[test]
fn split_passes_leave_the_one_thread_bits() {
    let mut r = Rnd(0x5b11_7000);
    let h = 1.0 / 240.0;
    let mut helped = 0;
    for round in 0..6 {
        let bodies: Vec<SolverBody> = (0..3000).map(|_| random_body(&mut r)).collect();
        let fixed = 300;
        let constraints: Vec<ContactConstraint> = (0..2000)
            .map(|i| random_contact(&mut r, &bodies, i < fixed))
            .collect();
        let mut batches = ContactBatches::default();
        batches.build(&constraints, &bodies, fixed);
        let split_levels = batches.steps.iter().filter(|s| split::chunks(s).is_some());
        assert!(split_levels.count() > 2, "round {round}: no wide levels");
        let (steps, fixed_steps) = (batches.steps.len(), batches.fixed_steps);
        let mut split_batches = ContactBatches::default();
        split_batches.build(&constraints, &bodies, fixed);
        let (mut one, mut two) = (bodies.clone(), bodies.clone());
        let (mut c1, mut c2) = (constraints.clone(), constraints.clone());
        warm_start_steps(&mut one, &c1, &batches, 0..steps);
        helped += split::warm_start_steps(Runner::Thread, &mut two, &c2, &split_batches, 0..steps);
        assert_same(&one, &two, &format!("round {round}: warm start"));
        for (pass, use_bias) in [true, false, true].into_iter().enumerate() {
            // Nothing moves the bodies between passes: only the first measures.
            for (range, measure) in [(0..steps, pass == 0), (0..fixed_steps, false)] {
                let kind = Pass {
                    h,
                    use_bias,
                    measure,
                };
                let serial = solve_steps(&mut one, &mut c1, &mut batches, range.clone(), &[], kind);
                let (b, c, s) = (&mut two, &mut c2, &mut split_batches);
                let (work, ran) = split::solve_steps(Runner::Thread, b, c, s, range, &[], kind);
                helped += ran;
                // The same work, however the levels were shared out.
                assert_eq!(work, serial, "round {round}, pass {pass}: work");
            }
            assert_same(&one, &two, &format!("round {round}, pass {pass}"));
        }
    }
    // The helper ran every chunk of every wide level.
    assert!(helped > 0, "the helper ran no chunk");
}
