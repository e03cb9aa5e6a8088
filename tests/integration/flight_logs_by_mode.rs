//! The flight logs of `rotorpilot run` without `--log`, end to end in the runtime: the vehicle
//! logs into its directory of the per-user default place (`ROOT/instance-0`, named by the ready
//! line), as `SDLOG_MODE` says, announces each log as PX4's logger does ("[logger]
//! ./log/YYYY-MM-DD/HH_MM_SS.ulg"), and serves it over the log protocol (LOG_REQUEST_LIST,
//! LOG_REQUEST_DATA) byte for byte. Mode 0 (the default) logs from arming to disarming, 1 from
//! start until the first disarming and then per arming, 4 from the first arming on, −1 never;
//! 3 is refused at start with the reason.
#![allow(deprecated, clippy::unwrap_used, clippy::expect_used)]

use crate::support;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU16, Ordering};
use std::time::Duration;

use mavlink::dialects::ardupilotmega::*;
use rotorpilot::airframe::AirframeSource;
use rotorpilot::control::ControllerKind;
use rotorpilot::runners::bench::autopilot::InProcess;
use rotorpilot::runtime::log_place::LogPlace;
use rotorpilot::runtime::RunConfig;
use support::Autopilot;

/// How long to listen after a command, or at start, for the logger's announcement.
const LISTEN: Duration = Duration::from_millis(500);

/// A fresh state directory standing for `~/.local/state` (nothing in it).
fn state(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rotorpilot-state-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The per-user default place below `state`.
fn place(state: &Path) -> LogPlace {
    LogPlace::Default {
        root: state.join("rotorpilot"),
        first_instance: 0,
    }
}

/// A vehicle on the exact state (armable at once) logging into `state`, `SDLOG_MODE` = `mode`
/// when given (as `--params` sets it).
fn start(state: &Path, mode: Option<i32>) -> Autopilot {
    Autopilot::start_with(1, "quad_x", |c| {
        c.log = Some(place(state));
        c.params
            .extend(mode.map(|m| ("test".into(), "SDLOG_MODE".into(), f64::from(m))));
    })
}

/// Arms (or disarms) and listens for `listen`: the logger's announcements meanwhile (the
/// command is sent once and its ACK read among them, so no announcement is skipped). Each
/// command differs in its unused `param7`, so none is a retransmission of the one before.
fn arm(ap: &mut Autopilot, on: bool, listen: Duration) -> Vec<String> {
    static SENT: AtomicU16 = AtomicU16::new(0);
    ap.send(&MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: if on { 1.0 } else { 0.0 },
        param7: f32::from(SENT.fetch_add(1, Ordering::Relaxed)),
        command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    }));
    let (texts, acks) = heard(ap, listen);
    assert_eq!(acks, vec![MavResult::MAV_RESULT_ACCEPTED], "arm {on}");
    texts
}

/// The logger's announcements and the COMMAND_ACK results heard within `listen`.
fn heard(ap: &Autopilot, listen: Duration) -> (Vec<String>, Vec<MavResult>) {
    let (mut texts, mut acks) = (Vec::new(), Vec::new());
    ap.wait(listen, |_, m| {
        match m {
            MavMessage::STATUSTEXT(t) => {
                let text = t.text.to_str().unwrap_or("").trim_end_matches('\0').to_string();
                if text.starts_with("[logger]") {
                    assert_eq!(t.severity, MavSeverity::MAV_SEVERITY_INFO, "{text}");
                    texts.push(text);
                }
            }
            MavMessage::COMMAND_ACK(a) => acks.push(a.result),
            _ => {}
        }
        None::<()>
    });
    (texts, acks)
}

/// LOG_REQUEST_LIST: (num_logs, each entry's size) in id order.
fn list(ap: &mut Autopilot) -> (u16, Vec<u32>) {
    ap.send(&MavMessage::LOG_REQUEST_LIST(LOG_REQUEST_LIST_DATA {
        start: 0,
        end: 0xFFFF,
        target_system: 1,
        target_component: 1,
    }));
    let mut sizes = Vec::new();
    let mut num_logs = u16::MAX;
    while let Some(e) = ap.wait(Duration::from_millis(500), |_, m| match m {
        MavMessage::LOG_ENTRY(e) => Some(e.clone()),
        _ => None,
    }) {
        num_logs = e.num_logs;
        if e.num_logs > 0 {
            sizes.push(e.size);
        }
        if usize::from(e.id) + 1 >= usize::from(e.num_logs) {
            break;
        }
    }
    (num_logs, sizes)
}

/// Log `id` of `size` bytes through LOG_REQUEST_DATA.
fn download(ap: &mut Autopilot, id: u16, size: u32) -> Vec<u8> {
    ap.send(&MavMessage::LOG_REQUEST_DATA(LOG_REQUEST_DATA_DATA {
        ofs: 0,
        count: size,
        id,
        target_system: 1,
        target_component: 1,
    }));
    let mut bytes = vec![0u8; size as usize];
    let mut got = 0;
    while got < size as usize {
        let Some(d) = ap.wait(Duration::from_secs(2), |_, m| match m {
            MavMessage::LOG_DATA(d) if d.id == id => Some(d.clone()),
            _ => None,
        }) else {
            break;
        };
        let (at, n) = (d.ofs as usize, usize::from(d.count));
        bytes[at..at + n].copy_from_slice(&d.data[..n]);
        got += n;
    }
    assert_eq!(got, size as usize, "log {id} whole");
    bytes
}

/// The ULog files below `dir`, oldest first.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for date in std::fs::read_dir(dir.join("log")).into_iter().flatten().flatten() {
        out.extend(std::fs::read_dir(date.path()).unwrap().flatten().map(|f| f.path()));
    }
    out.sort();
    out
}

#[test]
fn by_default_a_flight_is_logged_from_arming_to_disarming_announced_and_served() {
    let state = state("default");
    let dir = state.join("rotorpilot/instance-0");
    let mut ap = start(&state, None);
    assert_eq!(ap.ready().first.log_dir.as_deref(), dir.to_str());
    assert_eq!(list(&mut ap), (0, vec![]), "no flight, no log");
    assert!(!state.exists(), "nothing is created before a log begins");
    let said = arm(&mut ap, true, LISTEN);
    arm(&mut ap, false, LISTEN);
    let [path] = &files(&dir)[..] else {
        panic!("one log: {:?}", files(&dir))
    };
    let name = path.strip_prefix(&dir).unwrap().to_str().unwrap().to_string();
    assert_eq!(said, vec![format!("[logger] ./{name}")]);
    std::thread::sleep(Duration::from_millis(300)); // closed and flushed by the writer
    let on_disk = std::fs::read(path).unwrap();
    assert!(on_disk.starts_with(b"ULog\x01\x12\x35"), "a ULog file");
    let (num_logs, sizes) = list(&mut ap);
    assert_eq!((num_logs, sizes.clone()), (1, vec![on_disk.len() as u32]));
    assert_eq!(download(&mut ap, 0, sizes[0]), on_disk);
    assert!(!dir.join("flight.tlog").exists(), "the tlog only with --log");
    drop(ap);
    let _ = std::fs::remove_dir_all(state);
}

#[test]
fn sdlog_mode_1_logs_from_start_until_the_first_disarming_then_per_arming() {
    let state = state("boot");
    let dir = state.join("rotorpilot/instance-0");
    let mut ap = start(&state, Some(1));
    assert_eq!(heard(&ap, LISTEN).0.len(), 1, "a log from start");
    assert_eq!(list(&mut ap).0, 1, "listed while it is written");
    assert!(arm(&mut ap, true, LISTEN).is_empty(), "the start's log goes on");
    arm(&mut ap, false, LISTEN);
    assert_eq!(arm(&mut ap, true, LISTEN).len(), 1, "a new log");
    arm(&mut ap, false, LISTEN);
    assert_eq!(list(&mut ap).0, 2);
    assert_eq!(files(&dir).len(), 2);
    drop(ap);
    let _ = std::fs::remove_dir_all(state);
}

#[test]
fn sdlog_mode_4_logs_from_the_first_arming_on_and_minus_1_never() {
    let state = state("arm-on");
    let mut ap = start(&state, Some(4));
    assert_eq!(list(&mut ap).0, 0);
    let mut said = Vec::new();
    for on in [true, false, true, false] {
        said.extend(arm(&mut ap, on, LISTEN));
    }
    assert_eq!(said.len(), 1);
    assert_eq!(list(&mut ap).0, 1, "one file until the process stops");
    drop(ap);
    let _ = std::fs::remove_dir_all(&state);

    let mut ap = start(&state, Some(-1));
    assert!(arm(&mut ap, true, LISTEN).is_empty());
    arm(&mut ap, false, LISTEN);
    assert_eq!(list(&mut ap), (0, vec![]));
    drop(ap);
    assert!(!state.exists(), "disabled: nothing written");
}

#[test]
fn sdlog_mode_3_is_refused_at_start_with_the_reason() {
    let state = state("aux");
    let config = RunConfig {
        bind_gcs: "127.0.0.1:0".parse().unwrap(),
        bind_api: "127.0.0.1:0".parse().unwrap(),
        log: Some(place(&state)),
        params: vec![("my.params:1".into(), "SDLOG_MODE".into(), 3.0)],
        ..RunConfig::single(AirframeSource::resolve("quad_x").unwrap(), ControllerKind::Geometric, 1)
    };
    let Err(e) = InProcess::start(config) else {
        panic!("SDLOG_MODE 3 accepted")
    };
    let e = e.to_string();
    assert!(
        e.contains("my.params:1") && e.contains("SDLOG_MODE") && e.contains("AUX1"),
        "{e}"
    );
    assert!(!state.exists());
}
