//! Runs of one control law spread over worker threads by the engine sweeps use
//! ([`crate::runners::sweep_run::engine`]): a panicking run is counted instead of ending the campaign,
//! and results are stored by run index, so the thread count never changes a report.

use crate::control::ControllerKind;
use crate::runners::sweep_run::engine::map_guarded;

use super::envelope::Draw;
use super::stats::RunResult;
use super::trial::{fly, TrialError, TrialOutcome, TrialSetup};

/// Flies `kind` from every draw on `threads` worker threads (at least one).
pub fn fly_all(
    setup: &TrialSetup,
    kind: ControllerKind,
    draws: &[Draw],
    threads: usize,
) -> Result<Vec<RunResult>, TrialError> {
    run_guarded(draws, threads, |d| fly(setup, kind, d))
}

/// Calls `run` on every draw on `threads` worker threads (at least one), each call guarded by
/// `catch_unwind`. The first setup error ends the campaign.
pub fn run_guarded<F>(draws: &[Draw], threads: usize, run: F) -> Result<Vec<RunResult>, TrialError>
where
    F: Fn(&Draw) -> Result<TrialOutcome, TrialError> + Sync,
{
    Ok(map_guarded(draws, threads, &|_| {}, run)?
        .into_iter()
        .map(|r| r.map_or_else(RunResult::Panicked, RunResult::Flew))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lockstep::Exit;
    use crate::runners::montecarlo::envelope::{draws, Envelope};

    fn outcome(ticks: u64) -> TrialOutcome {
        TrialOutcome {
            end: Exit::Complete,
            converged: true,
            convergence_time_s: Some(0.0),
            final_position_error_m: 0.0,
            final_attitude_error_rad: 0.0,
            max_tilt_rad: 0.0,
            non_finite: false,
            fault_ticks: 0,
            saturated_ticks: 0,
            ticks,
        }
    }

    #[test]
    fn a_panicking_run_is_counted_and_the_others_finish_in_order() {
        let env = Envelope {
            max_tilt_rad: 1.0,
            max_rate_rad_s: 1.0,
            max_speed_m_s: 1.0,
            max_offset_m: 1.0,
            max_force_n: 1.0,
            max_torque_n_m: [0.1; 3],
        };
        let ds = draws(&env, 0, 7);
        let poisoned = ds[4].noise_seed;
        for threads in [1, 2, 16] {
            let results = run_guarded(&ds, threads, |d| {
                assert_ne!(d.noise_seed, poisoned, "boom");
                Ok(outcome(d.noise_seed % 1000))
            })
            .unwrap();
            assert_eq!(results.len(), 7);
            for (i, (r, d)) in results.iter().zip(&ds).enumerate() {
                match r {
                    RunResult::Panicked(msg) => assert!(i == 4 && msg.contains("boom"), "{i}: {msg}"),
                    RunResult::Flew(o) => assert_eq!(o.ticks, d.noise_seed % 1000, "run {i} in its slot"),
                }
            }
        }
    }

    #[test]
    fn a_setup_error_ends_the_campaign() {
        let ds = draws(&Envelope::HOVER, 0, 3);
        let err = run_guarded(&ds, 2, |_| Err(TrialError::Timing("bad".into()))).unwrap_err();
        assert_eq!(err, TrialError::Timing("bad".into()));
    }
}
