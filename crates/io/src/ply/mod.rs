//! Stanford PLY: ASCII, binary little endian and binary big endian (format
//! 1.0). Any elements are accepted; `vertex` and `face` are read, the rest
//! skipped. Written as binary little endian.

mod header;
mod read;
mod write;

pub(crate) use read::read;
pub(crate) use write::write;
