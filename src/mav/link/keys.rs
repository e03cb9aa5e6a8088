//! Message signing on the links (docs/mavlink.md §10): [`SigningKeys`] owns the key in force
//! and its replay state ([`Signing`]), the wall clock's epoch as a signing timestamp, whether
//! keys are kept in a key file, and where each stored key's result is to be announced.
//! SETUP_SIGNING is refused while armed; otherwise the key (all zero: off) applies at once to
//! every link and, with a key file, is stored, its result announced when the file answers.

use std::collections::VecDeque;

use mavlink::{MAVLinkMessageRaw, MAVLinkV2MessageRaw};

use super::boundary::KeyToStore;
use super::effects::Effect;
use super::{LinkKind, INFO, WARNING};
use crate::mav::signing::{Signing, SigningKey, Verdict};
use crate::mav::stream_messages::status_text;

/// The signing of every link and the key file's answers awaited.
#[derive(Debug)]
pub(super) struct SigningKeys<A> {
    signing: Signing,
    /// The wall clock at wall time 0, as a signing timestamp [10 µs since 2015] (0: no clock).
    epoch: u64,
    /// SETUP_SIGNING keys are written to a key file.
    key_store: bool,
    /// Where to announce each stored key's result (link, client, signing on), oldest first.
    in_store: VecDeque<(LinkKind, A, bool)>,
}

impl<A: Copy> SigningKeys<A> {
    /// `signing` in force, its clock `epoch` [10 µs since 2015], keys kept in a file when
    /// `key_store`.
    pub fn new(signing: Signing, epoch: u64, key_store: bool) -> Self {
        Self {
            signing,
            epoch,
            key_store,
            in_store: VecDeque::new(),
        }
    }

    /// The signing clock at wall time `wall_s` [s], as a timestamp [10 µs since 2015].
    pub fn now(&self, wall_s: f64) -> u64 {
        self.epoch + (wall_s.max(0.0) * 1e5) as u64
    }

    /// The signing timestamp to persist [10 µs since 2015].
    pub fn timestamp(&self) -> u64 {
        self.signing.timestamp()
    }

    /// Frames dropped so far (unsigned, wrongly signed or replayed).
    pub fn dropped(&self) -> u64 {
        self.signing.dropped().total()
    }

    /// The verdict on a received frame at signing time `stamp` [10 µs since 2015].
    pub fn check(&mut self, frame: &MAVLinkMessageRaw, stamp: u64) -> Verdict {
        self.signing.check(frame, stamp)
    }

    /// Seals an outgoing `frame` of link `link_id` at wall time `wall_s` [s] when signing is on.
    pub fn seal(&mut self, frame: &mut MAVLinkV2MessageRaw, link_id: u8, wall_s: f64) {
        if self.signing.enabled() {
            let stamp = self.now(wall_s);
            self.signing.seal(frame, link_id, stamp);
        }
    }

    /// SETUP_SIGNING from `from` on `link` with `key` and `initial_timestamp`, the vehicle
    /// `armed` or not. It reached here only unsigned with no key set, or signed with the
    /// current key.
    pub fn setup(
        &mut self,
        (link, from): (LinkKind, A),
        key: SigningKey,
        initial_timestamp: u64,
        armed: bool,
    ) -> Vec<Effect<A>> {
        if armed {
            let text = status_text(WARNING, "SETUP_SIGNING refused: disarm first");
            return vec![Effect::send(link, from, text)];
        }
        self.signing.set_key(key.clone(), initial_timestamp);
        let enabled = self.signing.enabled();
        if self.key_store {
            self.in_store.push_back((link, from, enabled));
            vec![Effect::Store(KeyToStore {
                key: enabled.then_some(key),
                timestamp: self.signing.timestamp(),
            })]
        } else {
            let state = if enabled { "Signing enabled" } else { "Signing disabled" };
            let text = status_text(INFO, &format!("{state} until restart"));
            vec![Effect::send(link, from, text)]
        }
    }

    /// The key file's answer to the oldest key stored.
    pub fn stored(&mut self, result: Result<(), String>) -> Vec<Effect<A>> {
        let Some((link, to, enabled)) = self.in_store.pop_front() else {
            return Vec::new();
        };
        let state = if enabled { "Signing enabled" } else { "Signing disabled" };
        let (severity, text) = match result {
            Ok(()) => (INFO, format!("{state}; key stored")),
            Err(_) => (WARNING, format!("{state}; key file not written")),
        };
        vec![Effect::send(link, to, status_text(severity, &text))]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::link::effects::testing::texts;

    #[test]
    fn a_key_is_refused_while_armed_and_stored_when_there_is_a_key_file() {
        let mut keys = SigningKeys::new(Signing::new(None, 0), 100, true);
        assert_eq!(keys.now(1.0), 100_100);
        let key = SigningKey::from_passphrase("secret");
        let out = keys.setup((LinkKind::Gcs, 7u16), key.clone(), 5, true);
        assert_eq!(texts(&out), vec!["SETUP_SIGNING refused: disarm first"]);
        let out = keys.setup((LinkKind::Gcs, 7u16), key.clone(), 5, false);
        assert!(matches!(&out[..], [Effect::Store(KeyToStore { key: Some(k), .. })] if *k == key));
        assert_eq!(texts(&keys.stored(Ok(()))), vec!["Signing enabled; key stored"]);
        assert!(keys.stored(Ok(())).is_empty(), "one answer per key stored");
    }

    #[test]
    fn without_a_key_file_the_key_holds_until_restart() {
        let mut keys = SigningKeys::new(Signing::new(None, 0), 0, false);
        let out = keys.setup((LinkKind::Api, 3u16), SigningKey::from_passphrase("k"), 1, false);
        assert_eq!(texts(&out), vec!["Signing enabled until restart"]);
        let out = keys.setup((LinkKind::Api, 3u16), SigningKey::from_bytes([0; 32]), 1, false);
        assert_eq!(texts(&out), vec!["Signing disabled until restart"]);
    }
}
