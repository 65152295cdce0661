//! A Digital Surf `.sur` file in the compressed layout, built from a plain
//! one's header and points: magic `DSCOMPRESSED`, then after the 512-byte
//! header a stream count, each stream's (raw, zipped) lengths and the zlib
//! streams (the layout Gwyddion's `surffile.c` reads). Shared by the unit
//! tests in `src/sur.rs` and the integration tests in `tests/sur.rs`.

use std::io::Write;

use flate2::Compression;
use flate2::write::ZlibEncoder;

/// `header` (the plain file's, magic replaced) followed by `points` split
/// into zlib streams of at most `stream_bytes` raw bytes.
pub fn compressed_sur(header: &[u8], points: &[u8], stream_bytes: usize) -> Vec<u8> {
    let mut file = header.to_vec();
    file[..12].copy_from_slice(b"DSCOMPRESSED");
    let streams: Vec<(usize, Vec<u8>)> = points
        .chunks(stream_bytes)
        .map(|part| {
            let mut encoder = ZlibEncoder::new(Vec::new(), Compression::fast());
            encoder.write_all(part).unwrap();
            (part.len(), encoder.finish().unwrap())
        })
        .collect();
    file.extend((streams.len() as u32).to_le_bytes());
    for (raw, zipped) in &streams {
        file.extend((*raw as u32).to_le_bytes());
        file.extend((zipped.len() as u32).to_le_bytes());
    }
    for (_, zipped) in &streams {
        file.extend(zipped);
    }
    file
}
