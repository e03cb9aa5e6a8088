//! The ULog file format (version 1) as bytes: the 16-byte file header and each message, appended
//! to a caller's buffer. Pure, and allocation-free once the buffer has grown: the tick thread
//! encodes its data messages here and hands whole buffers to a writer thread.
//!
//! Every message is a 3-byte header — payload size (u16, little-endian, header excluded) and a
//! type letter — then its payload, little-endian throughout:
//!
//! | type | message | payload |
//! |------|---------|---------|
//! | `B` | flag bits | 8 compatible flags, 8 incompatible flags, 3 appended-data offsets (u64) |
//! | `F` | format | `name:type field;type[n] field;…` (first field `uint64_t timestamp`) |
//! | `I` | info | key length (u8), key `type name`, value |
//! | `P` | parameter | as info; key `float NAME` or `int32_t NAME` |
//! | `A` | subscription | multi id (u8), message id (u16), topic name |
//! | `D` | data | message id (u16), the fields packed as the format declares them |
//! | `L` | logged string | level (ASCII `'0'`–`'7'`, syslog/MAVLink severity), timestamp (u64 µs), text |
//! | `S` | synchronisation | the 8 magic bytes [`SYNC_MAGIC`] |
//! | `O` | dropout | lost time (u16 ms) |
//!
//! Definitions (`B`, `F`, `I`, `P`) precede the data section; parameters may change in it.

/// The file magic: "ULog", then 0x01 0x12 0x35.
pub const FILE_MAGIC: [u8; 7] = [b'U', b'L', b'o', b'g', 0x01, 0x12, 0x35];
/// The format version written.
pub const VERSION: u8 = 1;
/// Payload of the synchronisation message.
pub const SYNC_MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];

/// A parameter value as ULog stores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamValue {
    /// `float` parameter.
    Float(f32),
    /// `int32_t` parameter.
    Int(i32),
}

/// Appends ULog messages to `out`.
#[derive(Debug)]
pub struct Encoder<'a> {
    /// Where the bytes go.
    pub out: &'a mut Vec<u8>,
}

impl<'a> Encoder<'a> {
    /// An encoder appending to `out`.
    pub fn new(out: &'a mut Vec<u8>) -> Self {
        Self { out }
    }

    /// The file header, timestamped `t_us` [µs].
    pub fn file_header(&mut self, t_us: u64) {
        self.out.extend_from_slice(&FILE_MAGIC);
        self.out.push(VERSION);
        self.out.extend_from_slice(&t_us.to_le_bytes());
    }

    /// A message header for a payload of `len` bytes, cut to what a u16 holds.
    fn header(&mut self, kind: u8, len: usize) {
        self.out
            .extend_from_slice(&(len.min(usize::from(u16::MAX)) as u16).to_le_bytes());
        self.out.push(kind);
    }

    /// The flag bits message: no flags, no appended data.
    pub fn flag_bits(&mut self) {
        self.header(b'B', 40);
        self.out.extend_from_slice(&[0; 40]);
    }

    /// A format message: `name:fields` (`fields` as `type name;` items).
    pub fn format(&mut self, name: &str, fields: &str) {
        self.header(b'F', name.len() + 1 + fields.len());
        self.out.extend_from_slice(name.as_bytes());
        self.out.push(b':');
        self.out.extend_from_slice(fields.as_bytes());
    }

    /// An info or parameter message of type `kind` with key `key` and value bytes `value`; a
    /// key longer than 255 bytes is cut.
    fn key_value(&mut self, kind: u8, key: &str, value: &[u8]) {
        let key = &key.as_bytes()[..key.len().min(255)];
        self.header(kind, 1 + key.len() + value.len());
        self.out.push(key.len() as u8);
        self.out.extend_from_slice(key);
        self.out.extend_from_slice(value);
    }

    /// An info message holding text: key `char[len] name`.
    pub fn info_text(&mut self, name: &str, text: &str) {
        let key = format!("char[{}] {name}", text.len());
        self.key_value(b'I', &key, text.as_bytes());
    }

    /// An info message holding a `uint32_t`.
    pub fn info_u32(&mut self, name: &str, value: u32) {
        self.key_value(b'I', &format!("uint32_t {name}"), &value.to_le_bytes());
    }

    /// An info message holding an `int32_t`.
    pub fn info_i32(&mut self, name: &str, value: i32) {
        self.key_value(b'I', &format!("int32_t {name}"), &value.to_le_bytes());
    }

    /// A parameter message (initial value in the definitions, a change in the data section).
    pub fn param(&mut self, name: &str, value: ParamValue) {
        match value {
            ParamValue::Float(v) => self.key_value(b'P', &format!("float {name}"), &v.to_le_bytes()),
            ParamValue::Int(v) => self.key_value(b'P', &format!("int32_t {name}"), &v.to_le_bytes()),
        }
    }

    /// Subscribes message id `msg_id` to topic `name`, instance 0.
    pub fn subscription(&mut self, msg_id: u16, name: &str) {
        self.header(b'A', 3 + name.len());
        self.out.push(0);
        self.out.extend_from_slice(&msg_id.to_le_bytes());
        self.out.extend_from_slice(name.as_bytes());
    }

    /// Starts a data message of `len` payload bytes after the message id; the caller appends
    /// exactly `len` bytes of fields.
    pub fn data(&mut self, msg_id: u16, len: usize) -> &mut Vec<u8> {
        let [s0, s1] = ((2 + len).min(usize::from(u16::MAX)) as u16).to_le_bytes();
        let [m0, m1] = msg_id.to_le_bytes();
        self.out.extend_from_slice(&[s0, s1, b'D', m0, m1]);
        self.out
    }

    /// A logged string at `level` (MAVLink severity 0 emergency … 7 debug) at `t_us` [µs].
    pub fn logged_string(&mut self, level: u8, t_us: u64, text: &str) {
        let text = &text.as_bytes()[..text.len().min(usize::from(u16::MAX) - 9)];
        self.header(b'L', 9 + text.len());
        self.out.push(b'0' + level.min(7));
        self.out.extend_from_slice(&t_us.to_le_bytes());
        self.out.extend_from_slice(text);
    }

    /// A synchronisation message.
    pub fn sync(&mut self) {
        self.header(b'S', SYNC_MAGIC.len());
        self.out.extend_from_slice(&SYNC_MAGIC);
    }

    /// A dropout of `ms` milliseconds (cut to 65535).
    pub fn dropout(&mut self, ms: u64) {
        self.header(b'O', 2);
        self.out
            .extend_from_slice(&(ms.min(u64::from(u16::MAX)) as u16).to_le_bytes());
    }
}

/// Appends little-endian field values to a data message.
pub trait Fields {
    /// A `uint64_t`.
    fn u64(&mut self, v: u64) -> &mut Self;
    /// A `float` (`v` rounded to single precision).
    fn f32(&mut self, v: f64) -> &mut Self;
    /// Three `float`s.
    fn f32x3(&mut self, v: [f64; 3]) -> &mut Self;
    /// A `double`.
    fn f64(&mut self, v: f64) -> &mut Self;
    /// A `uint32_t`.
    fn u32(&mut self, v: u32) -> &mut Self;
    /// An `int32_t`.
    fn i32(&mut self, v: i32) -> &mut Self;
    /// A `uint8_t`.
    fn u8(&mut self, v: u8) -> &mut Self;
    /// A `bool` (one byte).
    fn bool(&mut self, v: bool) -> &mut Self;
}

impl Fields for Vec<u8> {
    fn u64(&mut self, v: u64) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }

    fn f32(&mut self, v: f64) -> &mut Self {
        self.extend_from_slice(&(v as f32).to_le_bytes());
        self
    }

    fn f32x3(&mut self, v: [f64; 3]) -> &mut Self {
        let mut bytes = [0u8; 12];
        for (chunk, x) in bytes.chunks_exact_mut(4).zip(v) {
            chunk.copy_from_slice(&(x as f32).to_le_bytes());
        }
        self.extend_from_slice(&bytes);
        self
    }

    fn f64(&mut self, v: f64) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }

    fn u32(&mut self, v: u32) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }

    fn i32(&mut self, v: i32) -> &mut Self {
        self.extend_from_slice(&v.to_le_bytes());
        self
    }

    fn u8(&mut self, v: u8) -> &mut Self {
        self.push(v);
        self
    }

    fn bool(&mut self, v: bool) -> &mut Self {
        self.push(u8::from(v));
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_file_header_is_sixteen_bytes() {
        let mut out = Vec::new();
        Encoder::new(&mut out).file_header(0x0102);
        assert_eq!(out.len(), 16);
        assert_eq!(&out[..7], b"ULog\x01\x12\x35");
        assert_eq!(out[7], 1);
        assert_eq!(u64::from_le_bytes(out[8..16].try_into().unwrap()), 0x0102);
    }

    #[test]
    fn each_message_carries_its_payload_size_and_type() {
        let mut out = Vec::new();
        let mut e = Encoder::new(&mut out);
        e.format("t", "uint64_t timestamp;");
        let len = u16::from_le_bytes([out[0], out[1]]) as usize;
        assert_eq!((len, out[2], out.len()), (21, b'F', 24));
        assert_eq!(&out[3..], b"t:uint64_t timestamp;");
    }

    #[test]
    fn info_and_parameters_name_their_type_in_the_key() {
        let mut out = Vec::new();
        let mut e = Encoder::new(&mut out);
        e.info_text("sys_name", "rp");
        e.param("MPC_XY_VEL_MAX", ParamValue::Float(12.0));
        let key_len = out[3] as usize;
        assert_eq!(&out[4..4 + key_len], b"char[2] sys_name");
        assert_eq!(&out[4 + key_len..4 + key_len + 2], b"rp");
        let p = &out[4 + key_len + 2..];
        assert_eq!(p[2], b'P');
        assert_eq!(&p[4..4 + p[3] as usize], b"float MPC_XY_VEL_MAX");
        assert_eq!(&p[p.len() - 4..], &12.0f32.to_le_bytes());
    }

    #[test]
    fn a_data_message_counts_the_id_and_the_fields() {
        let mut out = Vec::new();
        let mut e = Encoder::new(&mut out);
        e.data(3, 9).u64(7).bool(true);
        assert_eq!(out, [11, 0, b'D', 3, 0, 7, 0, 0, 0, 0, 0, 0, 0, 1]);
    }

    #[test]
    fn a_logged_string_has_an_ascii_level() {
        let mut out = Vec::new();
        Encoder::new(&mut out).logged_string(2, 5, "hi");
        assert_eq!(out, [11, 0, b'L', b'2', 5, 0, 0, 0, 0, 0, 0, 0, b'h', b'i']);
    }
}
