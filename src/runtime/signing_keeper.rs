//! The signing state every vehicle starts from ([`SigningSetup`]: key and timestamp, loaded from
//! `--signing-key FILE`) and the task that keeps it ([`signing_keeper`]: persists the newest
//! timestamp, reports dropped frames). Runtime layer.

use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::watch;

use crate::mav::signing::SigningKey;

use super::link::SigningStatus;
use super::signing_store::{signing_now, SigningFileError, SigningStore};

/// The signing key and timestamp every vehicle starts from, and where they are kept.
pub(super) struct SigningSetup {
    pub key: Option<SigningKey>,
    /// Start timestamp: the persisted one or the wall clock, whichever is later [10 µs].
    pub timestamp: u64,
    pub store: Option<Arc<SigningStore>>,
}

impl SigningSetup {
    pub fn load(key_path: Option<std::path::PathBuf>) -> Result<Self, SigningFileError> {
        let Some(path) = key_path else {
            return Ok(Self {
                key: None,
                timestamp: signing_now(),
                store: None,
            });
        };
        let store = SigningStore::new(path);
        let (key, stored) = store.load()?;
        Ok(Self {
            key,
            timestamp: stored.max(signing_now()),
            store: Some(Arc::new(store)),
        })
    }
}

/// How often the signing timestamp is persisted and dropped frames are reported.
const SIGNING_KEEP_PERIOD: Duration = Duration::from_secs(10);

/// Persists the latest signing timestamp of all vehicles every [`SIGNING_KEEP_PERIOD`] and once
/// more when `links_stopped` says every link task has ended (at least once a minute, and never
/// behind a frame sent), and logs how many frames signing dropped.
pub(super) async fn signing_keeper(
    vehicles: Vec<Arc<SigningStatus>>,
    store: Option<Arc<SigningStore>>,
    start_timestamp: u64,
    mut links_stopped: watch::Receiver<bool>,
) {
    let mut reported = 0;
    let mut period = tokio::time::interval(SIGNING_KEEP_PERIOD);
    loop {
        let stopping = tokio::select! {
            _ = links_stopped.changed() => true,
            _ = period.tick() => false,
        };
        // Never below the timestamp the vehicles started from (before their first frame).
        let (mut timestamp, mut dropped) = (start_timestamp, 0);
        for status in &vehicles {
            timestamp = timestamp.max(status.timestamp.load(Ordering::Relaxed));
            dropped += status.dropped.load(Ordering::Relaxed);
        }
        if dropped > reported {
            tracing::warn!("signing: {dropped} frames dropped (unsigned, wrongly signed or replayed)");
            reported = dropped;
        }
        if let Some(store) = &store {
            if let Err(e) = store.save_timestamp(timestamp) {
                tracing::warn!("signing timestamp file: {e}");
            }
        }
        if stopping {
            break;
        }
    }
}
