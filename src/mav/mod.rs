//! MAVLink: the only module that names the `mavlink` crate (architecture.md §3).

pub mod codec;
