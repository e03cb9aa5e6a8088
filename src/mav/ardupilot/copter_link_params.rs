//! ArduCopter's parameters that the link holds, not the parameter table (docs/ardupilot.md §5.2):
//! `SYSID_THISMAV`, the vehicle's system id, and `SRn_*`, the rate of each of Copter's stream
//! groups ([`CopterGroup`]) on link `n` (SR0 the first link, the ground station's; SR1 the
//! second, the API's). [`LinkParams`] is what the link holds, read from it when a parameter is
//! shown (never kept beside it); the view shows these after the table's parameters, so the
//! table's indices stay the same. A PARAM_SET of `SRn_*` sets the group's rate as
//! REQUEST_DATA_STREAM does; one of `SYSID_THISMAV` is refused unless it names the system id
//! the vehicle has (it is fixed at start, `--sysid`). Pure.

use super::copter_params::CopterType;
use super::copter_streams::{CopterGroup, GROUP_COUNT};
use crate::mav::ftp::PackedValue;

/// Copter's name of the system id.
pub const SYSID_THISMAV: &str = "SYSID_THISMAV";

/// What the link holds that ArduCopter shows as parameters, read from the link.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LinkParams {
    /// The vehicle's MAVLink system id.
    pub system_id: u8,
    /// Each link's rate of each group [Hz], in link order, groups in [`CopterGroup::ALL`]'s.
    pub stream_rates: Vec<[u16; GROUP_COUNT]>,
}

/// One parameter the link holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkParam {
    /// `SYSID_THISMAV`.
    SystemId,
    /// `SR{link}_{group}`.
    StreamRate {
        /// The link's place (0 the first).
        link: usize,
        /// The group.
        group: CopterGroup,
    },
}

impl LinkParam {
    /// Copter's name (`SYSID_THISMAV`, `SR0_POSITION`).
    pub fn name(self) -> String {
        match self {
            Self::SystemId => SYSID_THISMAV.to_string(),
            Self::StreamRate { link, group } => format!("SR{link}_{}", group.suffix()),
        }
    }
}

/// What a PARAM_SET of a link-held parameter asks of the link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkSet {
    /// Nothing changes (`SYSID_THISMAV` set to the id it has); the value is echoed.
    Unchanged,
    /// The rate of `group` on link `link` becomes `rate_hz` (0: off).
    StreamRate {
        /// The link's place.
        link: usize,
        /// The group.
        group: CopterGroup,
        /// The rate [Hz].
        rate_hz: u16,
    },
}

/// True for a name of what the link holds, on any link (`SYSID_THISMAV`, `SR0_POSITION`,
/// `SR5_ADSB`).
pub fn is_link_param(name: &str) -> bool {
    let stream_rate = || {
        let rest = name.strip_prefix("SR")?;
        let (n, suffix) = rest.split_once('_')?;
        let numbered = !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit());
        Some(numbered && CopterGroup::ALL.iter().any(|g| g.suffix() == suffix))
    };
    name == SYSID_THISMAV || stream_rate() == Some(true)
}

/// Both are AP_Int16 in Copter.
const KIND: CopterType = CopterType::Int16;

impl LinkParams {
    /// Number of parameters held: `SYSID_THISMAV` and ten per link.
    pub fn len(&self) -> usize {
        1 + GROUP_COUNT * self.stream_rates.len()
    }

    /// Never empty (`SYSID_THISMAV` is always there).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The parameter at place `k` (0 `SYSID_THISMAV`, then `SR0_*` in Copter's order, `SR1_*`).
    pub fn param(&self, k: usize) -> Option<LinkParam> {
        if k == 0 {
            return Some(LinkParam::SystemId);
        }
        let (link, group) = ((k - 1) / GROUP_COUNT, (k - 1) % GROUP_COUNT);
        (link < self.stream_rates.len()).then(|| LinkParam::StreamRate {
            link,
            group: CopterGroup::ALL[group],
        })
    }

    /// Place of the parameter Copter calls `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        (0..self.len()).find(|k| self.param(*k).is_some_and(|p| p.name() == name))
    }

    /// Value and Copter's default of the parameter at place `k`, as Copter stores them (INT16).
    pub fn value(&self, k: usize) -> Option<(PackedValue, PackedValue)> {
        let (value, default) = match self.param(k)? {
            LinkParam::SystemId => (u16::from(self.system_id), 1),
            LinkParam::StreamRate { link, group } => (self.stream_rates.get(link)?[group.index()], 0),
        };
        Some((KIND.stored(f64::from(value)), KIND.stored(f64::from(default))))
    }

    /// What a PARAM_SET of the parameter at place `k` to `value` (the float as sent) asks, or
    /// why it is refused (`SR0_POSITION: -1 outside [0, 32767]`, `SYSID_THISMAV: fixed at
    /// start (--sysid)`); `None` past the end.
    pub fn set(&self, k: usize, value: f64) -> Option<Result<LinkSet, String>> {
        let param = self.param(k)?;
        let name = param.name();
        let number = KIND.from_set(value);
        if !number.is_finite() {
            return Some(Err(format!("{name}: {value} is not a number")));
        }
        Some(match param {
            LinkParam::SystemId if number == f64::from(self.system_id) => Ok(LinkSet::Unchanged),
            LinkParam::SystemId => Err(format!("{name}: fixed at start (--sysid)")),
            LinkParam::StreamRate { link, group } => {
                let max = i16::MAX;
                if (0.0..=f64::from(max)).contains(&number) {
                    Ok(LinkSet::StreamRate {
                        link,
                        group,
                        rate_hz: number as u16,
                    })
                } else {
                    Err(format!("{name}: {number} outside [0, {max}]"))
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_links() -> LinkParams {
        let mut gcs = [0; GROUP_COUNT];
        gcs[CopterGroup::Position.index()] = 4;
        LinkParams {
            system_id: 7,
            stream_rates: vec![gcs, [0; GROUP_COUNT]],
        }
    }

    #[test]
    fn the_system_id_then_ten_rates_per_link() {
        let p = two_links();
        assert_eq!(p.len(), 21);
        assert_eq!(p.param(0), Some(LinkParam::SystemId));
        let names: Vec<String> = (0..p.len()).filter_map(|k| p.param(k)).map(LinkParam::name).collect();
        assert_eq!(names[..3], ["SYSID_THISMAV", "SR0_RAW_SENS", "SR0_EXT_STAT"]);
        assert_eq!(names[10..13], ["SR0_ADSB", "SR1_RAW_SENS", "SR1_EXT_STAT"]);
        assert_eq!(names[20], "SR1_ADSB");
        assert_eq!(p.param(21), None);
        assert_eq!(p.index_of("SR0_POSITION"), Some(5));
        assert_eq!(p.index_of("SR2_POSITION"), None, "no third link");
        assert_eq!(p.value(0), Some((PackedValue::Int16(7), PackedValue::Int16(1))));
        assert_eq!(p.value(5), Some((PackedValue::Int16(4), PackedValue::Int16(0))));
        assert_eq!(p.value(16), Some((PackedValue::Int16(0), PackedValue::Int16(0))));
    }

    #[test]
    fn sets_ask_the_link_or_are_refused() {
        let p = two_links();
        let position_1 = p.index_of("SR1_POSITION").unwrap_or(0);
        assert_eq!(
            p.set(position_1, 9.999),
            Some(Ok(LinkSet::StreamRate {
                link: 1,
                group: CopterGroup::Position,
                rate_hz: 10
            }))
        );
        assert_eq!(p.set(5, -1.0), Some(Err("SR0_POSITION: -1 outside [0, 32767]".into())));
        assert_eq!(
            p.set(5, f64::NAN),
            Some(Err("SR0_POSITION: NaN is not a number".into()))
        );
        assert_eq!(p.set(0, 7.0), Some(Ok(LinkSet::Unchanged)));
        assert_eq!(
            p.set(0, 2.0),
            Some(Err("SYSID_THISMAV: fixed at start (--sysid)".into()))
        );
        assert_eq!(p.set(21, 1.0), None);
    }

    #[test]
    fn link_names_are_known_on_any_link() {
        for name in ["SYSID_THISMAV", "SR0_POSITION", "SR6_ADSB", "SR12_EXTRA1"] {
            assert!(is_link_param(name), "{name}");
        }
        for name in ["SR_POSITION", "SRX_POSITION", "SR0_NOPE", "SR0POSITION", "WPNAV_SPEED"] {
            assert!(!is_link_param(name), "{name}");
        }
    }
}
