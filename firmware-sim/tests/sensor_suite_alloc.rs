//! `SensorSuite::read` allocates nothing on the heap, whatever the faults (docs/model.md §10.1):
//! a counting global allocator watches this thread while the suite runs.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

use firmware_sim::{GeoSite, Plant, PlantParams, SensorFault, SensorSuite, SensorSuiteConfig, SensorUnit, TruthState};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static WATCHING: Cell<bool> = const { Cell::new(false) };
}

// SAFETY: every call is forwarded unchanged to the system allocator; the counter only observes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if WATCHING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if WATCHING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made on this thread while `f` runs.
fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    WATCHING.with(|w| w.set(true));
    f();
    WATCHING.with(|w| w.set(false));
    ALLOCATIONS.load(Ordering::Relaxed) - before
}

#[test]
fn reading_the_suite_never_allocates() {
    assert!(
        allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) >= 1,
        "the counter counts"
    );
    let params = PlantParams::from_toml_str(include_str!("../../airframes/quad_x.toml"), "quad_x").unwrap();
    let truth0: TruthState = Plant::new(params).truth();
    let faults = [
        SensorFault::Ok,
        SensorFault::Off,
        SensorFault::Stuck,
        SensorFault::Garbage,
        SensorFault::Wrong,
        SensorFault::SLOW,
        SensorFault::DELAYED,
        SensorFault::INTERMITTENT,
    ];
    for config in [SensorSuiteConfig::typical(), SensorSuiteConfig::ideal()] {
        let mut suite = SensorSuite::new(config, &GeoSite::PX4_DEFAULT_HOME, 1).unwrap();
        let mut delivered = 0usize;
        let n = allocations_during(|| {
            for (phase, fault) in faults.iter().enumerate() {
                for unit in SensorUnit::ALL {
                    suite.set_fault(unit, *fault);
                }
                for i in 0..3000u64 {
                    let mut truth = truth0;
                    truth.t_s = ((phase as u64 * 3000 + i) * 1_000_000) as f64 * 1e-9;
                    let r = suite.read(&truth);
                    delivered += usize::from(r.imu.is_some()) + usize::from(r.gps.is_some());
                }
            }
        });
        assert_eq!(n, 0, "allocations during 24 000 reads");
        assert!(delivered > 15_000, "the suite did deliver ({delivered})");
    }
}
