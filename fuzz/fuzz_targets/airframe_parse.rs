//! Airframe file text → both readers of it: the flight controller's `Airframe::from_source`
//! and the plant's `SimPlant::from_source`; when both accept it, the whole vehicle is built
//! (allocation, controller, estimator) and flown for a few ticks. A bad file must be refused
//! with an error naming the field, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

use rotorpilot::airframe::{Airframe, AirframeSource};
use rotorpilot::commander::Request;
use rotorpilot::control::ControllerKind;
use rotorpilot::guidance::Home;
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::{SensorModel, SimPlant};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let src = AirframeSource {
        origin: "fuzz.toml".into(),
        text: text.to_string(),
    };
    let fc = Airframe::from_source(&src);
    if let Err(e) = &fc {
        assert!(
            !e.field.is_empty() && !e.reason.is_empty(),
            "error without field or reason: {e:?}"
        );
    }
    let plant = SimPlant::from_source(&src, 0);
    if let Err(e) = &plant {
        assert!(!e.to_string().is_empty());
    }
    let (Ok(fc), Ok(_)) = (fc, plant) else {
        return;
    };
    assert!(fc.rotors.len() >= rotorpilot::airframe::MIN_ROTORS);
    for kind in [ControllerKind::Geometric, ControllerKind::Passivity] {
        let Ok(mut vehicle) = Vehicle::new(&src, kind, Home::default(), SensorModel::State, 0, 1e-3) else {
            continue;
        };
        vehicle.apply(Request::Arm { force: true });
        vehicle.apply(Request::Takeoff { height_m: Some(1.0) });
        for _ in 0..20 {
            vehicle.step();
        }
    }
});
