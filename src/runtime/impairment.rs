//! Link impairment (`rotorpilot run --link-loss 20% --link-delay 0..50ms --link-duplicate 5%
//! --link-seed N`): a bad radio link between the vehicle and its clients, built in, so that a
//! ground station or a companion computer can be tried against loss, duplicates, delay and the
//! reordering that delay brings, reproducibly. Each datagram crossing an impaired link, in each
//! direction, is dropped with probability `loss`; one that passes is sent twice with probability
//! `duplicate`; each copy is held for a delay drawn uniformly from the delay range. The draws
//! come from one ChaCha8 stream per link and direction, seeded from `--link-seed`, the vehicle
//! and the link, so a run is reproducible as far as the datagrams' order is.
//!
//! Pure: the time is passed in ([s] of the caller's clock); the runtime's link task feeds the
//! datagrams through [`Impairments`] and sends or reads them when they are due.

use std::collections::BTreeMap;

use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use thiserror::Error;

use crate::mav::streams::LinkKind;
use crate::sweep::design::unit;

/// What happens to the datagrams going one way.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Impairment {
    /// Probability that a datagram is dropped [0–1].
    pub loss: f64,
    /// Probability that a datagram that passes is sent twice [0–1].
    pub duplicate: f64,
    /// Delay range of each copy, uniform [s].
    pub delay_s: DelayRange,
}

/// The impairment of a vehicle's links: to the vehicle (`up`) and from it (`down`).
#[derive(Debug, Clone, PartialEq)]
pub struct LinkImpairment {
    /// Datagrams from the clients to the vehicle.
    pub up: Impairment,
    /// Datagrams from the vehicle to the clients.
    pub down: Impairment,
    /// The links impaired (GCS, API or both).
    pub links: Vec<LinkKind>,
    /// Seed of the draws; vehicle i draws from `seed + i`.
    pub seed: u64,
}

impl LinkImpairment {
    /// The impairment of `run`'s options: `--link-loss`, `--link-delay`, `--link-duplicate` (each
    /// `UP/DOWN` or one value for both ways), `--link-impaired` (`gcs`, `api`, `all`) and
    /// `--link-seed`; `None` when none of the first three is given.
    pub fn from_options(
        loss: Option<&str>,
        delay: Option<&str>,
        duplicate: Option<&str>,
        links: &str,
        seed: u64,
    ) -> Result<Option<Self>, ImpairmentError> {
        if loss.is_none() && delay.is_none() && duplicate.is_none() {
            return Ok(None);
        }
        let (loss_up, loss_down) = loss.map_or(Ok((0.0, 0.0)), |t| parse_probabilities("link-loss", t))?;
        let (dup_up, dup_down) = duplicate.map_or(Ok((0.0, 0.0)), |t| parse_probabilities("link-duplicate", t))?;
        let (delay_up, delay_down) = delay.map_or(Ok(((0.0, 0.0), (0.0, 0.0))), parse_delays)?;
        let links = match links.trim() {
            "all" => vec![LinkKind::Gcs, LinkKind::Api],
            "gcs" => vec![LinkKind::Gcs],
            "api" => vec![LinkKind::Api],
            _ => {
                return Err(ImpairmentError {
                    option: "link-impaired",
                    value: links.to_string(),
                    why: "the links are gcs, api or all",
                })
            }
        };
        Ok(Some(Self {
            up: Impairment {
                loss: loss_up,
                duplicate: dup_up,
                delay_s: delay_up,
            },
            down: Impairment {
                loss: loss_down,
                duplicate: dup_down,
                delay_s: delay_down,
            },
            links,
            seed,
        }))
    }
}

/// A `--link-*` value that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("--{option} {value:?}: {why}")]
pub struct ImpairmentError {
    /// The option, without its dashes.
    pub option: &'static str,
    /// The value given.
    pub value: String,
    /// What is wrong with it.
    pub why: &'static str,
}

/// `text` split as `UP/DOWN`, or the same value both ways.
fn both_ways(text: &str) -> (&str, &str) {
    text.split_once('/').unwrap_or((text, text))
}

/// A probability written `20%` or `0.2`, per direction (`UP/DOWN`).
pub fn parse_probabilities(option: &'static str, text: &str) -> Result<(f64, f64), ImpairmentError> {
    let err = |why| ImpairmentError {
        option,
        value: text.to_string(),
        why,
    };
    let one = |s: &str| -> Result<f64, ImpairmentError> {
        let s = s.trim();
        let p = match s.strip_suffix('%') {
            Some(pct) => pct.trim().parse::<f64>().map(|v| v / 100.0),
            None => s.parse::<f64>(),
        }
        .map_err(|_| err("a probability is a percentage (20%) or a fraction (0.2); UP/DOWN for each direction"))?;
        if !(0.0..=1.0).contains(&p) {
            return Err(err("a probability lies between 0% and 100%"));
        }
        Ok(p)
    };
    let (up, down) = both_ways(text);
    Ok((one(up)?, one(down)?))
}

/// A delay range (shortest, longest) [s].
pub type DelayRange = (f64, f64);

/// A delay range written `0..50ms`, `20ms` or `0.1s`, per direction (`UP/DOWN`) [s].
pub fn parse_delays(text: &str) -> Result<(DelayRange, DelayRange), ImpairmentError> {
    let err = |why| ImpairmentError {
        option: "link-delay",
        value: text.to_string(),
        why,
    };
    let seconds = |s: &str, unit: f64| -> Result<f64, ImpairmentError> {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| err("a delay is a number with ms or s: 0..50ms, 20ms, 0.1s"))?;
        if !(v.is_finite() && v >= 0.0) {
            return Err(err("a delay is 0 or more"));
        }
        Ok(v * unit)
    };
    let one = |s: &str| -> Result<DelayRange, ImpairmentError> {
        let s = s.trim();
        let (number, unit) = if let Some(ms) = s.strip_suffix("ms") {
            (ms, 1e-3)
        } else if let Some(sec) = s.strip_suffix('s') {
            (sec, 1.0)
        } else {
            return Err(err("a delay needs its unit: ms or s (0..50ms, 20ms, 0.1s)"));
        };
        let (lo, hi) = match number.split_once("..") {
            Some((lo, hi)) => (seconds(lo, unit)?, seconds(hi, unit)?),
            None => (seconds(number, unit)?, seconds(number, unit)?),
        };
        if lo > hi {
            return Err(err("a delay range goes from the shorter to the longer"));
        }
        if hi > 10.0 {
            return Err(err("a delay is at most 10 s"));
        }
        Ok((lo, hi))
    };
    let (up, down) = both_ways(text);
    Ok((one(up)?, one(down)?))
}

/// What happened to the datagrams going one way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct ImpairCounts {
    /// Datagrams offered.
    pub datagrams: u64,
    /// Dropped.
    pub dropped: u64,
    /// Sent twice.
    pub duplicated: u64,
    /// Copies held for a delay above zero.
    pub delayed: u64,
}

/// One direction of one link: the draws and the datagrams held back.
#[derive(Debug)]
struct Channel<T> {
    spec: Impairment,
    rng: ChaCha8Rng,
    counts: ImpairCounts,
    /// Held copies by due time [ns] and arrival order.
    held: BTreeMap<(u64, u64), T>,
    next_id: u64,
}

impl<T: Clone> Channel<T> {
    fn new(spec: Impairment, seed: u64) -> Self {
        Self {
            spec,
            rng: ChaCha8Rng::seed_from_u64(seed),
            counts: ImpairCounts::default(),
            held: BTreeMap::new(),
            next_id: 0,
        }
    }

    /// `item` offered at `now_s`: the copies to deliver now (the others are held).
    fn offer(&mut self, now_s: f64, item: T) -> Vec<T> {
        self.counts.datagrams += 1;
        if unit(&mut self.rng) < self.spec.loss {
            self.counts.dropped += 1;
            return Vec::new();
        }
        let copies = if unit(&mut self.rng) < self.spec.duplicate {
            self.counts.duplicated += 1;
            2
        } else {
            1
        };
        let mut now = Vec::new();
        for _ in 0..copies {
            let (lo, hi) = self.spec.delay_s;
            let delay = lo + (hi - lo) * unit(&mut self.rng);
            if delay <= 0.0 {
                now.push(item.clone());
                continue;
            }
            self.counts.delayed += 1;
            let due_ns = ((now_s + delay) * 1e9) as u64;
            self.held.insert((due_ns, self.next_id), item.clone());
            self.next_id += 1;
        }
        now
    }

    /// The held copies due by `now_s`, in due order.
    fn due(&mut self, now_s: f64, out: &mut Vec<T>) {
        let now_ns = (now_s * 1e9) as u64;
        while self.held.first_key_value().is_some_and(|((due, _), _)| *due <= now_ns) {
            out.extend(self.held.pop_first().map(|(_, item)| item));
        }
    }

    fn next_due_s(&self) -> Option<f64> {
        self.held.first_key_value().map(|((due, _), _)| *due as f64 * 1e-9)
    }
}

/// What one link's impairment did, both ways.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct LinkCounts {
    /// "gcs" or "api".
    pub link: &'static str,
    /// To the vehicle.
    pub up: ImpairCounts,
    /// From the vehicle.
    pub down: ImpairCounts,
}

/// The impaired links of one vehicle; `T` is a datagram as the caller keeps it.
#[derive(Debug)]
pub struct Impairments<T> {
    links: Vec<(LinkKind, Channel<T>, Channel<T>)>,
}

impl<T: Clone> Impairments<T> {
    /// The impairment of vehicle `index` as `config` says.
    pub fn new(config: &LinkImpairment, index: usize) -> Self {
        let seed = config.seed.wrapping_add(index as u64);
        let links = config
            .links
            .iter()
            .map(|&link| {
                // One stream per link and direction, all from the vehicle's seed.
                let base = seed
                    .wrapping_mul(4)
                    .wrapping_add(if link == LinkKind::Gcs { 0 } else { 2 });
                (
                    link,
                    Channel::new(config.up, base),
                    Channel::new(config.down, base.wrapping_add(1)),
                )
            })
            .collect();
        Self { links }
    }

    /// A datagram on `link` at `now_s`, towards the vehicle when `up`: what passes now.
    pub fn offer(&mut self, now_s: f64, link: LinkKind, up: bool, item: T) -> Vec<T> {
        match self.links.iter_mut().find(|(l, ..)| *l == link) {
            Some((_, to_vehicle, _)) if up => to_vehicle.offer(now_s, item),
            Some((_, _, from_vehicle)) => from_vehicle.offer(now_s, item),
            None => vec![item],
        }
    }

    /// The held datagrams due by `now_s`: (to the vehicle, from the vehicle).
    pub fn due(&mut self, now_s: f64) -> (Vec<T>, Vec<T>) {
        let (mut up, mut down) = (Vec::new(), Vec::new());
        for (_, to_vehicle, from_vehicle) in &mut self.links {
            to_vehicle.due(now_s, &mut up);
            from_vehicle.due(now_s, &mut down);
        }
        (up, down)
    }

    /// When the next held datagram is due [s].
    pub fn next_due_s(&self) -> Option<f64> {
        self.links
            .iter()
            .flat_map(|(_, a, b)| [a.next_due_s(), b.next_due_s()])
            .flatten()
            .min_by(f64::total_cmp)
    }

    /// What each impaired link did so far.
    pub fn counts(&self) -> Vec<LinkCounts> {
        self.links
            .iter()
            .map(|(link, up, down)| LinkCounts {
                link: if *link == LinkKind::Gcs { "gcs" } else { "api" },
                up: up.counts,
                down: down.counts,
            })
            .collect()
    }
}

#[cfg(test)]
#[path = "impairment_tests.rs"]
mod tests;
