//! VTK XML unstructured grid (.vtu): every encoding, compressor, header type and byte order.
//!
//! Reading goes `xml` (structure, via quick-xml events) -> `source` (where an array's bytes are:
//! inline text or the appended block, in memory or in the file) -> `block` (binary headers,
//! decompression) -> `decode` (bytes or ascii into typed arrays) -> `read` (one merged [`Grid`]).
//! Writing is `write`; `.pvtu` is `pvtu`.

pub mod base64;
mod block;
mod decode;
pub mod pvtu;
mod read;
mod source;
mod write;
mod xml;

pub(crate) use read::merge;
pub use read::{read, read_path};
pub use write::write;

/// Integer type of the size headers in front of binary data (`header_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeaderType {
    UInt32,
    UInt64,
}

impl HeaderType {
    pub fn size(self) -> usize {
        match self {
            HeaderType::UInt32 => 4,
            HeaderType::UInt64 => 8,
        }
    }
}

/// Byte order of binary data (`byte_order`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ByteOrder {
    LittleEndian,
    BigEndian,
}

impl ByteOrder {
    pub fn native() -> ByteOrder {
        if cfg!(target_endian = "big") {
            ByteOrder::BigEndian
        } else {
            ByteOrder::LittleEndian
        }
    }
}

/// Block compressor of binary data (`compressor`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compressor {
    None,
    Zlib,
    Lz4,
    Lzma,
}

impl Compressor {
    pub fn from_vtk_name(name: &str) -> Option<Compressor> {
        match name {
            "" => Some(Compressor::None),
            "vtkZLibDataCompressor" => Some(Compressor::Zlib),
            "vtkLZ4DataCompressor" => Some(Compressor::Lz4),
            "vtkLZMADataCompressor" => Some(Compressor::Lzma),
            _ => None,
        }
    }

    pub fn vtk_name(self) -> &'static str {
        match self {
            Compressor::None => "",
            Compressor::Zlib => "vtkZLibDataCompressor",
            Compressor::Lz4 => "vtkLZ4DataCompressor",
            Compressor::Lzma => "vtkLZMADataCompressor",
        }
    }
}

/// How every binary block of a file is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub header: HeaderType,
    pub order: ByteOrder,
    pub compressor: Compressor,
}
