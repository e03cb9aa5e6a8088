//! The parameters as one packed file, ArduPilot's `@PARAM/param.pck` format as PX4 serves and
//! accepts it over MAVLink FTP. Pure.
//!
//! A 6-byte little-endian header: the magic ([`MAGIC`], or [`MAGIC_WITH_DEFAULTS`] when defaults
//! may follow the values), the number of entries in the file, and a total: on a download the
//! number of parameters the vehicle has, on an upload the length of the file in bytes. Then one
//! entry per parameter, in wire order, each perhaps preceded by zero bytes of padding:
//! - a type byte: the low nibble the value's type (1 int8, 2 int16, 3 int32, 4 float: PX4
//!   serves only the last two, ArduPilot all four), bit 4 set when the parameter's default
//!   follows its value;
//! - a name byte: the number of leading characters shared with the previous entry's name in the
//!   low nibble, the number of new characters minus one in the high nibble (a name repeated whole
//!   is sent as sharing all but its last character);
//! - the new characters, then the value and, when flagged, the default (little endian).
//!
//! A download pads so that no value or default straddles a block of the size it is read in
//! (239 bytes, one FTP frame), and adds a default only where it differs from the value (the
//! receiver takes a missing default as the value), as PX4 does. An upload carries neither
//! defaults nor the defaults' magic; int8 and int16 values widen to int32.

use thiserror::Error;

/// The magic of a file without defaults.
pub const MAGIC: u16 = 0x671B;
/// The magic of a file whose entries may carry their default.
pub const MAGIC_WITH_DEFAULTS: u16 = 0x671C;
/// The path of the packed file, before any query (`?withdefaults=1`, `start=`, `count=`).
pub const PARAM_FILE: &str = "@PARAM/param.pck";
/// Bytes of the header.
pub const HEADER_LEN: usize = 6;
/// Longest parameter name [characters] (MAVLink's `param_id`).
pub const NAME_MAX: usize = 16;

/// Type nibbles.
const TYPE_INT8: u8 = 1;
const TYPE_INT16: u8 = 2;
const TYPE_INT32: u8 = 3;
const TYPE_FLOAT: u8 = 4;
/// Flag of the type byte: a default follows the value.
const HAS_DEFAULT: u8 = 0x10;

/// A parameter value as the packed file (and PARAM_VALUE) carries it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PackedValue {
    /// An 8-bit signed integer (ArduPilot's AP_Int8; PX4 has none).
    Int8(i8),
    /// A 16-bit signed integer (ArduPilot's AP_Int16; PX4 has none).
    Int16(i16),
    /// A 32-bit signed integer (MAV_PARAM_TYPE_INT32).
    Int32(i32),
    /// A 32-bit float (MAV_PARAM_TYPE_REAL32).
    Float(f32),
}

impl PackedValue {
    /// The value bytes as a little-endian word: the integer's two's complement (sign-extended
    /// from int8 and int16) or the float's IEEE-754 bits.
    pub fn bits(self) -> u32 {
        match self {
            Self::Int8(v) => i32::from(v) as u32,
            Self::Int16(v) => i32::from(v) as u32,
            Self::Int32(v) => v as u32,
            Self::Float(v) => v.to_bits(),
        }
    }

    /// The value as a number, as a PARAM_SET of this type decodes it.
    pub fn as_f64(self) -> f64 {
        match self {
            Self::Int8(v) => f64::from(v),
            Self::Int16(v) => f64::from(v),
            Self::Int32(v) => f64::from(v),
            Self::Float(v) => f64::from(v),
        }
    }

    /// The type nibble.
    fn type_nibble(self) -> u8 {
        match self {
            Self::Int8(_) => TYPE_INT8,
            Self::Int16(_) => TYPE_INT16,
            Self::Int32(_) => TYPE_INT32,
            Self::Float(_) => TYPE_FLOAT,
        }
    }

    /// Bytes of the value in a packed file (1, 2 or 4).
    fn len(self) -> usize {
        match self {
            Self::Int8(_) => 1,
            Self::Int16(_) => 2,
            Self::Int32(_) | Self::Float(_) => 4,
        }
    }

    /// The value's bytes in a packed file, little endian.
    fn write(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.bits().to_le_bytes()[..self.len()]);
    }
}

/// One parameter of a download: name, value and default (of the same type).
#[derive(Debug, Clone, PartialEq)]
pub struct PackedParam {
    /// Name (1 to [`NAME_MAX`] ASCII characters).
    pub name: String,
    /// The value now.
    pub value: PackedValue,
    /// The default (of the same type).
    pub default: PackedValue,
}

/// One entry read from a packed file.
#[derive(Debug, Clone, PartialEq)]
pub struct PackedEntry {
    /// Name.
    pub name: String,
    /// Value (int8 and int16 widened to int32).
    pub value: PackedValue,
    /// The default, when the entry carries one.
    pub default: Option<PackedValue>,
}

/// A packed file read back.
#[derive(Debug, Clone, PartialEq)]
pub struct PackedFile {
    /// The magic ([`MAGIC`] or [`MAGIC_WITH_DEFAULTS`]).
    pub magic: u16,
    /// The header's total (parameters of the vehicle, or bytes of an upload).
    pub total: u16,
    /// The entries, in file order.
    pub entries: Vec<PackedEntry>,
}

/// What a download asks for: `?start=N&count=N&withdefaults=0|1` after the path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Query {
    /// Index of the first parameter.
    pub start: u64,
    /// Parameters at most (0: every one from `start` on).
    pub count: u64,
    /// `withdefaults` (0 or 1; anything else is refused).
    pub with_defaults: u64,
}

/// Why a packed file could not be made or read (an upload's fault fits a STATUSTEXT after
/// `param.pck: `).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PckError {
    /// The query asks for nothing that exists.
    #[error("bad query: {0}")]
    Query(String),
    /// A name the format cannot carry.
    #[error("parameter name {0:?} cannot be packed (1 to 16 ASCII characters)")]
    Name(String),
    /// More parameters than the 16-bit header counts.
    #[error("{0} parameters do not fit a packed file")]
    TooMany(usize),
    /// Shorter than its header or an entry.
    #[error("truncated at byte {0}")]
    Truncated(usize),
    /// Not a packed file.
    #[error("bad magic {0:#06x}")]
    Magic(u16),
    /// An upload with defaults.
    #[error("defaults in an upload")]
    Defaults,
    /// An upload whose header's length is not the file's.
    #[error("header says {header} bytes, file has {actual}")]
    Length {
        /// The header's total.
        header: usize,
        /// Bytes received.
        actual: usize,
    },
    /// An unknown type or flag.
    #[error("bad type byte {byte:#04x} at byte {offset}")]
    Type {
        /// Offset of the type byte.
        offset: usize,
        /// The byte.
        byte: u8,
    },
    /// A name that shares more than the previous one has, is longer than 16 or not ASCII.
    #[error("bad name at byte {0}")]
    BadName(usize),
    /// The header's count is not the number of entries.
    #[error("header counts {header} entries, file has {found}")]
    Count {
        /// The header's count.
        header: usize,
        /// Entries found.
        found: usize,
    },
}

/// True when `path` (with or without a leading `/`) names the packed file, with or without a query.
pub fn is_param_path(path: &str) -> bool {
    let path = path.strip_prefix('/').unwrap_or(path);
    path.strip_prefix(PARAM_FILE)
        .is_some_and(|rest| rest.is_empty() || rest.starts_with('?'))
}

/// The leading decimal digits of `text` as a number (0 without any), saturating, as `strtoul`.
fn leading_number(text: &str) -> u64 {
    text.bytes()
        .take_while(u8::is_ascii_digit)
        .fold(0u64, |n, d| n.saturating_mul(10).saturating_add(u64::from(d - b'0')))
}

impl Query {
    /// The query of `path`: the `start`, `count` and `withdefaults` items after `?` (separated by
    /// `&`; others ignored, a missing one 0).
    pub fn of(path: &str) -> Self {
        let mut query = Self::default();
        let Some((_, items)) = path.split_once('?') else {
            return query;
        };
        for item in items.split('&') {
            if let Some(v) = item.strip_prefix("start=") {
                query.start = leading_number(v);
            } else if let Some(v) = item.strip_prefix("count=") {
                query.count = leading_number(v);
            } else if let Some(v) = item.strip_prefix("withdefaults=") {
                query.with_defaults = leading_number(v);
            }
        }
        query
    }
}

/// The common prefix and the new characters of `name` after `previous`, as the name byte counts
/// them; `None` for a name the format cannot carry.
fn prefix(previous: &str, name: &str) -> Option<(usize, usize)> {
    if name.is_empty() || name.len() > NAME_MAX || !name.bytes().all(|b| b.is_ascii_graphic()) {
        return None;
    }
    let common = previous.bytes().zip(name.bytes()).take_while(|(a, b)| a == b).count();
    // A suffix of nothing cannot be said: the last shared character is sent again.
    let common = common.min(name.len() - 1);
    Some((common, name.len() - common))
}

/// The packed file of `params` (every parameter of the vehicle, in wire order) as `query` asks
/// for it, padded for reads of `block` bytes.
pub fn encode(params: &[PackedParam], query: Query, block: usize) -> Result<Vec<u8>, PckError> {
    let total = u16::try_from(params.len()).map_err(|_| PckError::TooMany(params.len()))?;
    let start = usize::try_from(query.start).unwrap_or(usize::MAX);
    if start >= params.len() {
        return Err(PckError::Query(format!(
            "start {} of {} parameters",
            query.start,
            params.len()
        )));
    }
    if query.count >= u64::from(u16::MAX) || query.with_defaults > 1 || block == 0 {
        return Err(PckError::Query(format!("{query:?}")));
    }
    let left = params.len() - start;
    let num = match usize::try_from(query.count) {
        Ok(count) if count > 0 => count.min(left),
        _ => left,
    };
    let with_defaults = query.with_defaults == 1;
    let magic = if with_defaults { MAGIC_WITH_DEFAULTS } else { MAGIC };
    let mut out = Vec::with_capacity(HEADER_LEN + num * 16);
    for word in [magic, num as u16, total] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    let mut previous = "";
    for p in &params[start..start + num] {
        let (common, new) = prefix(previous, &p.name).ok_or_else(|| PckError::Name(p.name.clone()))?;
        let default = (with_defaults && p.default.bits() != p.value.bits()).then_some(p.default);
        let data_len = p.value.len() * (1 + usize::from(default.is_some()));
        // Zero bytes first, so that the value (and default) lie within one block.
        let end_in_block = (out.len() + 2 + new + data_len) % block;
        if end_in_block > 0 && end_in_block < data_len {
            out.resize(out.len() + data_len - end_in_block, 0);
        }
        let flag = if default.is_some() { HAS_DEFAULT } else { 0 };
        out.push(p.value.type_nibble() | flag);
        out.push(common as u8 | (((new - 1) as u8) << 4));
        out.extend_from_slice(&p.name.as_bytes()[common..]);
        p.value.write(&mut out);
        if let Some(d) = default {
            d.write(&mut out);
        }
        previous = &p.name;
    }
    Ok(out)
}

/// Bytes `len` from `at` of `bytes`, or where it ends.
fn take(bytes: &[u8], at: usize, len: usize) -> Result<&[u8], PckError> {
    bytes.get(at..at + len).ok_or(PckError::Truncated(bytes.len()))
}

/// The value of type `nibble` in `raw` (its length checked), int8 and int16 widened.
fn value_of(nibble: u8, raw: &[u8]) -> PackedValue {
    let word = |n: usize| {
        let mut b = [0u8; 4];
        b[..n].copy_from_slice(&raw[..n]);
        b
    };
    match nibble {
        TYPE_INT8 => PackedValue::Int32(i32::from(raw[0] as i8)),
        TYPE_INT16 => PackedValue::Int32(i32::from(i16::from_le_bytes([raw[0], raw[1]]))),
        TYPE_INT32 => PackedValue::Int32(i32::from_le_bytes(word(4))),
        _ => PackedValue::Float(f32::from_le_bytes(word(4))),
    }
}

/// Reads a packed file (either magic); every entry must be whole and the header's count right.
pub fn decode(bytes: &[u8]) -> Result<PackedFile, PckError> {
    let header = take(bytes, 0, HEADER_LEN)?;
    let word = |i: usize| u16::from_le_bytes([header[i], header[i + 1]]);
    let (magic, num, total) = (word(0), word(2), word(4));
    if magic != MAGIC && magic != MAGIC_WITH_DEFAULTS {
        return Err(PckError::Magic(magic));
    }
    let (mut entries, mut previous, mut at) = (Vec::new(), String::new(), HEADER_LEN);
    while at < bytes.len() {
        if bytes[at] == 0 {
            at += 1;
            continue;
        }
        let [kind, names] = [bytes[at], take(bytes, at + 1, 1)?[0]];
        let value_len = match kind & 0x0F {
            TYPE_INT8 => 1,
            TYPE_INT16 => 2,
            TYPE_INT32 | TYPE_FLOAT => 4,
            _ => 0,
        };
        if value_len == 0 || kind & 0xE0 != 0 {
            return Err(PckError::Type { offset: at, byte: kind });
        }
        let (common, new) = (usize::from(names & 0x0F), usize::from(names >> 4) + 1);
        let tail = take(bytes, at + 2, new)?;
        if common > previous.len() || common + new > NAME_MAX || !tail.iter().all(u8::is_ascii_graphic) {
            return Err(PckError::BadName(at));
        }
        let name: String = previous[..common]
            .chars()
            .chain(tail.iter().map(|b| char::from(*b)))
            .collect();
        at += 2 + new;
        let value = value_of(kind & 0x0F, take(bytes, at, value_len)?);
        at += value_len;
        let default = if kind & HAS_DEFAULT != 0 {
            let d = value_of(kind & 0x0F, take(bytes, at, value_len)?);
            at += value_len;
            Some(d)
        } else {
            None
        };
        entries.push(PackedEntry {
            name: name.clone(),
            value,
            default,
        });
        previous = name;
    }
    if entries.len() != usize::from(num) {
        return Err(PckError::Count {
            header: usize::from(num),
            found: entries.len(),
        });
    }
    Ok(PackedFile { magic, total, entries })
}

/// The names and values of an uploaded file, in file order, as PX4 accepts one: magic
/// [`MAGIC`], the header's total the file's length, no defaults, every entry whole.
pub fn parse_upload(bytes: &[u8]) -> Result<Vec<(String, PackedValue)>, PckError> {
    let file = decode(bytes)?;
    if file.magic != MAGIC || file.entries.iter().any(|e| e.default.is_some()) {
        return Err(PckError::Defaults);
    }
    if usize::from(file.total) != bytes.len() {
        return Err(PckError::Length {
            header: usize::from(file.total),
            actual: bytes.len(),
        });
    }
    Ok(file.entries.into_iter().map(|e| (e.name, e.value)).collect())
}

#[cfg(test)]
#[path = "param_pck_tests.rs"]
mod tests;
