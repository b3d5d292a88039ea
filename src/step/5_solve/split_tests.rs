//! Split passes against the one-thread pass they stand for: on many random contacts
//! among many bodies (wide levels), a helper thread taking chunks of each level beside
//! the leader must leave every velocity bit for bit as the plain pass does.

use super::crew::{Crew, StopOnDrop};
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

/// The crew (one helper for all of a step's passes, see `crew.rs`): a helper thread
/// serving every pass in turn, running every chunk of every wide level, must leave the
/// one-thread bits too, and take every pass it was offered.
#[test]
fn a_crew_serving_every_pass_leaves_the_one_thread_bits() {
    let mut r = Rnd(0x00c7_e3a1);
    let h = 1.0 / 240.0;
    let bodies: Vec<SolverBody> = (0..3000).map(|_| random_body(&mut r)).collect();
    let fixed = 300;
    let constraints: Vec<ContactConstraint> = (0..2000)
        .map(|i| random_contact(&mut r, &bodies, i < fixed))
        .collect();
    let mut batches = ContactBatches::default();
    batches.build(&constraints, &bodies, fixed);
    let (steps, fixed_steps) = (batches.steps.len(), batches.fixed_steps);
    let mut crew_batches = ContactBatches::default();
    crew_batches.build(&constraints, &bodies, fixed);
    let (mut one, mut two) = (bodies.clone(), bodies.clone());
    let (mut c1, mut c2) = (constraints.clone(), constraints.clone());
    let crew = Crew::new(false);
    let mut helped = 0;
    std::thread::scope(|scope| {
        let crew = &crew;
        scope.spawn(move || crew.serve());
        let _stop = StopOnDrop(crew);
        for substep in 0..3 {
            let runner = Runner::Crew(crew);
            warm_start_steps(&mut one, &c1, &batches, 0..steps);
            helped += split::warm_start_steps(runner, &mut two, &c2, &crew_batches, 0..steps);
            assert_same(&one, &two, &format!("substep {substep}: warm start"));
            for (pass, use_bias) in [true, false].into_iter().enumerate() {
                for (range, measure) in [(0..steps, pass == 0), (0..fixed_steps, false)] {
                    let kind = Pass {
                        h,
                        use_bias,
                        measure,
                    };
                    let serial =
                        solve_steps(&mut one, &mut c1, &mut batches, range.clone(), &[], kind);
                    let (b, c, s) = (&mut two, &mut c2, &mut crew_batches);
                    let (work, ran) = split::solve_steps(runner, b, c, s, range, &[], kind);
                    helped += ran;
                    assert_eq!(work, serial, "substep {substep}, pass {pass}: work");
                }
                assert_same(&one, &two, &format!("substep {substep}, pass {pass}"));
            }
        }
    });
    // The leader claimed nothing: the helper ran every chunk of every split level.
    let chunks: u32 = batches.steps.iter().filter_map(split::chunks).sum();
    let fixed_chunks: u32 = batches.steps[..fixed_steps]
        .iter()
        .filter_map(split::chunks)
        .sum();
    assert_eq!(helped, 3 * (3 * chunks + 2 * fixed_chunks));
}
