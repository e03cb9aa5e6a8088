//! The autopilot under measurement (runtime layer): `rotorpilot run` on a thread of this process
//! ([`InProcess`], also the MAVLink integration tests' vehicle), or the command line that runs
//! it as a child process on loopback ([`loopback_run`], the start-up benchmark and the flood
//! test).

use std::net::SocketAddr;
use std::path::Path;
use std::process::Command;
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::Duration;

use super::BenchError;
use crate::runtime::{self, Ready, RunConfig, RunReport, RuntimeError};

/// How long [`InProcess::start`] waits for the autopilot to report ready.
const START_TIMEOUT: Duration = Duration::from_secs(60);

/// `rotorpilot run` on a thread of this process; stopped on [`InProcess::finish`] or drop.
pub struct InProcess {
    ready: Ready,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<JoinHandle<Result<RunReport, RuntimeError>>>,
}

impl InProcess {
    /// Runs `config` and waits (up to a minute) until its sockets are bound.
    pub fn start(config: RunConfig) -> Result<Self, BenchError> {
        let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
        let (ready_tx, ready_rx) = mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("bench-autopilot".into())
            .spawn(move || {
                runtime::run(config, async move { drop(stop_rx.await) }, |ready| {
                    let _ = ready_tx.send(ready.clone());
                })
            })
            .map_err(|source| BenchError::Io {
                what: "autopilot thread",
                source,
            })?;
        let ready = match ready_rx.recv_timeout(START_TIMEOUT) {
            Ok(ready) => ready,
            Err(_) => {
                return match thread.join() {
                    Ok(Err(e)) => Err(e.into()),
                    _ => Err(BenchError::Silent("the autopilot did not start")),
                }
            }
        };
        Ok(Self {
            ready,
            stop: Some(stop_tx),
            thread: Some(thread),
        })
    }

    /// Where the autopilot's sockets are bound.
    pub fn ready(&self) -> &Ready {
        &self.ready
    }

    /// Every vehicle's GCS-link address and system id.
    pub fn vehicles(&self) -> Vec<(SocketAddr, u8)> {
        self.ready
            .vehicles
            .iter()
            .filter_map(|v| Some((v.gcs_bind.parse().ok()?, v.sysid)))
            .collect()
    }

    /// Stops the autopilot and returns what it did.
    pub fn finish(mut self) -> Result<RunReport, BenchError> {
        self.stop();
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(report)) => Ok(report?),
            _ => Err(BenchError::Silent("the autopilot thread panicked")),
        }
    }

    /// Asks the autopilot to stop (once).
    fn stop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
    }
}

impl Drop for InProcess {
    fn drop(&mut self) {
        self.stop();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// `exe run` with its GCS and API links on ephemeral loopback ports, the API's telemetry to the
/// discard port (127.0.0.1:9), the GCS link's to `gcs`, for `duration_s` [s] (stdio inherited
/// until the caller sets it).
pub fn loopback_run(exe: &Path, gcs: SocketAddr, duration_s: u32) -> Command {
    let mut command = Command::new(exe);
    command
        .args(["run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0"])
        .args(["--api", "127.0.0.1:9", "--gcs", &gcs.to_string()])
        .args(["--duration", &duration_s.to_string()])
        // A benchmark or test leaves nothing in the user's log directory.
        .arg("--no-log");
    command
}
