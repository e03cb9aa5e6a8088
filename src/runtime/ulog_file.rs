//! One ULog file for a whole headless run (`sim --out`, `fly --log`): a [`UlogStream`] that waits
//! for the writer instead of dropping, its own writer thread, and the lockstep [`Observer`] that
//! records every tick.

use std::path::Path;

use super::flight_log::{self, LogWriteError, LogWriter, UlogTarget};
use super::ulog_stream::UlogStream;
use crate::lockstep::{Exit, Observer, SnapshotReport, Tick, TickView};
use crate::sitl::SimPlant;
use crate::ulog::{LogInfo, ParamValue, Recorder};

/// A ULog file written while a run lasts.
#[derive(Debug)]
pub struct UlogFile {
    stream: UlogStream,
    writer: LogWriter,
}

impl UlogFile {
    /// Creates `path` (and its directory) and writes the definitions: `info` and `params`, the
    /// log starting at `t_s` [s].
    pub fn create(
        path: &Path,
        recorder: Recorder,
        info: &LogInfo,
        params: &[(String, ParamValue)],
        t_s: f64,
    ) -> std::io::Result<Self> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        // Fail here, not in the writer thread, when the file cannot be created.
        std::fs::File::create(path)?;
        let (sender, writer) = flight_log::start(None, None, None)?;
        let mut stream = UlogStream::new(recorder, sender, true);
        stream.open(UlogTarget::File(path.to_path_buf()), t_s, info, params);
        Ok(Self { stream, writer })
    }

    /// Writes what is left and closes the file; the first write error names the file.
    pub fn finish(self) -> Result<(), LogWriteError> {
        let Self { stream, writer } = self;
        drop(stream);
        writer.finish()
    }
}

/// Records every tick; never stops the run.
impl<R: SnapshotReport> Observer<R> for UlogFile {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        self.stream.record(&TickView::of(tick, plant));
        None
    }
}
