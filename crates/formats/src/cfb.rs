//! Streams of a Compound File Binary (OLE2 structured storage) file, the
//! container of Digital Surf `.mnt` documents, read after Microsoft's
//! [MS-CFB] specification: a 512-byte header (sector size, the first
//! sectors of the directory, mini FAT and DIFAT, and the first 109 FAT
//! sector numbers), the FAT as chains of sector numbers, 128-byte directory
//! entries (UTF-16 name, type, first sector, size), and streams under 4096
//! bytes kept in the mini stream in 64-byte mini sectors.
//!
//! Only what reading one stream by name needs is implemented. Every chain
//! is followed at most as many steps as the file has sectors (a loop is an
//! error), and no buffer is larger than the file.

use crate::bytes::{ByteOrder, Bytes};
use crate::{Format, FormatError};

pub(crate) const MAGIC: &[u8] = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1";

const END_OF_CHAIN: u32 = 0xFFFF_FFFE;
const FREE: u32 = 0xFFFF_FFFF;
const HEADER_DIFAT: usize = 109;
const ENTRY_LEN: usize = 128;
const STREAM: u8 = 2;
const ROOT: u8 = 5;

/// An opened compound file: its FAT, mini FAT and directory.
pub(crate) struct Compound<'a> {
    bytes: Bytes<'a>,
    format: Format,
    sector_len: usize,
    mini_cutoff: usize,
    fat: Vec<u32>,
    mini_fat: Vec<u32>,
    /// the directory entries: name, type, first sector, size
    entries: Vec<(String, u8, u32, u64)>,
}

impl<'a> Compound<'a> {
    /// Parses the header, FAT, directory and mini FAT of `data`.
    pub(crate) fn open(data: &'a [u8], format: Format) -> Result<Self, FormatError> {
        let bytes = Bytes::new(data, format.name(), ByteOrder::Little);
        if !data.starts_with(MAGIC) {
            return Err(format.invalid("not a compound file (OLE2 signature missing)"));
        }
        let shift = bytes.read::<u16>(30, "the sector shift")?;
        if shift != 9 && shift != 12 {
            return Err(format.invalid(format!("byte 30: sector shift {shift}, expected 9 or 12")));
        }
        let mut compound = Compound {
            bytes,
            format,
            sector_len: 1 << shift,
            mini_cutoff: bytes.read::<u32>(56, "the mini stream cutoff")? as usize,
            fat: Vec::new(),
            mini_fat: Vec::new(),
            entries: Vec::new(),
        };
        compound.fat = compound.read_fat()?;
        let directory = compound.chain(bytes.read::<u32>(48, "the first directory sector")?)?;
        compound.entries = directory
            .chunks_exact(ENTRY_LEN)
            .map(|entry| {
                let e = Bytes::new(entry, format.name(), ByteOrder::Little);
                let name_len = usize::from(e.read::<u16>(64, "a name length").unwrap_or(0));
                let units: Vec<u16> = e
                    .values::<u16>(0, name_len.min(64) / 2, "a name")
                    .unwrap_or_default();
                let name = String::from_utf16_lossy(&units)
                    .trim_end_matches('\0')
                    .to_string();
                let kind = e.read::<u8>(66, "an entry type").unwrap_or(0);
                let start = e.read::<u32>(116, "a first sector").unwrap_or(END_OF_CHAIN);
                let size = e.read::<u64>(120, "a stream size").unwrap_or(0);
                (name, kind, start, size)
            })
            .collect();
        let mini_start = bytes.read::<u32>(60, "the first mini FAT sector")?;
        let mini_fat = compound.chain(mini_start)?;
        compound.mini_fat = Bytes::new(&mini_fat, format.name(), ByteOrder::Little).values::<u32>(
            0,
            mini_fat.len() / 4,
            "the mini FAT",
        )?;
        Ok(compound)
    }

    /// The sectors' count: the bound of every chain.
    fn sectors(&self) -> usize {
        self.bytes.len() / self.sector_len
    }

    /// The bytes of sector `n` (sector 0 follows the header).
    fn sector(&self, n: u32) -> Result<&'a [u8], FormatError> {
        let at = (n as usize + 1).saturating_mul(self.sector_len);
        self.bytes
            .slice(at, self.sector_len, &format!("compound-file sector {n}"))
    }

    /// The FAT: the sectors the header's and the DIFAT's entries name.
    fn read_fat(&self) -> Result<Vec<u32>, FormatError> {
        let count = self.bytes.read::<u32>(44, "the FAT sector count")? as usize;
        if count > self.sectors() {
            return Err(self.format.invalid(format!(
                "byte 44: {count} FAT sectors in a file of {} sectors",
                self.sectors()
            )));
        }
        let mut fat_sectors = self
            .bytes
            .values::<u32>(76, HEADER_DIFAT, "the header's DIFAT")?;
        let mut next = self.bytes.read::<u32>(68, "the first DIFAT sector")?;
        let per_sector = self.sector_len / 4;
        for _ in 0..self.sectors() {
            if next == END_OF_CHAIN || next == FREE || fat_sectors.len() >= count + per_sector {
                break;
            }
            let sector = Bytes::new(self.sector(next)?, self.format.name(), ByteOrder::Little);
            fat_sectors.extend(sector.values::<u32>(0, per_sector - 1, "a DIFAT sector")?);
            next = sector.read::<u32>(self.sector_len - 4, "the next DIFAT sector")?;
        }
        let mut fat = Vec::with_capacity(count * per_sector);
        for &n in fat_sectors.iter().take(count) {
            let sector = Bytes::new(self.sector(n)?, self.format.name(), ByteOrder::Little);
            fat.extend(sector.values::<u32>(0, per_sector, "a FAT sector")?);
        }
        Ok(fat)
    }

    /// The bytes of the chain of sectors from `start` (FAT or mini FAT).
    fn follow<'b>(
        &self,
        start: u32,
        table: &[u32],
        read: &dyn Fn(u32) -> Result<&'b [u8], FormatError>,
        limit: usize,
    ) -> Result<Vec<u8>, FormatError> {
        let mut out = Vec::new();
        let mut next = start;
        for _ in 0..=limit {
            if next == END_OF_CHAIN || next == FREE {
                return Ok(out);
            }
            out.extend_from_slice(read(next)?);
            next = *table.get(next as usize).ok_or_else(|| {
                self.format
                    .invalid(format!("compound-file sector {next} is not in the FAT"))
            })?;
        }
        Err(self
            .format
            .invalid(format!("the compound-file chain from sector {start} loops")))
    }

    /// A chain of regular sectors.
    fn chain(&self, start: u32) -> Result<Vec<u8>, FormatError> {
        self.follow(start, &self.fat, &|n| self.sector(n), self.sectors())
    }

    /// The bytes of the stream named `name` (the first entry of that name).
    pub(crate) fn stream(&self, name: &str) -> Result<Vec<u8>, FormatError> {
        let Some(&(_, _, start, size)) = self
            .entries
            .iter()
            .find(|(n, kind, _, _)| n == name && *kind == STREAM)
        else {
            return Err(self
                .format
                .invalid(format!("the compound file has no stream \"{name}\"")));
        };
        let size = usize::try_from(size)
            .ok()
            .filter(|&s| s <= self.bytes.len())
            .ok_or_else(|| {
                self.format
                    .invalid(format!("stream \"{name}\": {size} bytes exceed the file"))
            })?;
        let mut content = if size < self.mini_cutoff {
            let root = self.entries.iter().find(|(_, kind, _, _)| *kind == ROOT);
            let mini_stream = self.chain(root.map_or(END_OF_CHAIN, |r| r.2))?;
            let mini = |n: u32| -> Result<&[u8], FormatError> {
                let at = n as usize * 64;
                mini_stream.get(at..at + 64).ok_or_else(|| {
                    self.format
                        .invalid(format!("mini sector {n} is outside the mini stream"))
                })
            };
            self.follow(start, &self.mini_fat, &mini, mini_stream.len() / 64)?
        } else {
            self.chain(start)?
        };
        if content.len() < size {
            return Err(self.format.invalid(format!(
                "stream \"{name}\" holds {} bytes of its {size}",
                content.len()
            )));
        }
        content.truncate(size);
        Ok(content)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version-3 compound file: sector 0 the FAT, 1 the directory (root
    /// and a stream "A" of 4600 bytes, over the mini-stream cutoff), 2–10
    /// the stream, chained 2 → 3 → … → 10.
    fn file() -> (Vec<u8>, Vec<u8>) {
        let mut f = vec![0u8; 512 * 12];
        f[..8].copy_from_slice(MAGIC);
        f[26..28].copy_from_slice(&3u16.to_le_bytes());
        f[28..30].copy_from_slice(&0xFFFEu16.to_le_bytes());
        f[30..32].copy_from_slice(&9u16.to_le_bytes());
        f[32..34].copy_from_slice(&6u16.to_le_bytes());
        let put =
            |f: &mut Vec<u8>, at: usize, v: u32| f[at..at + 4].copy_from_slice(&v.to_le_bytes());
        put(&mut f, 44, 1);
        put(&mut f, 48, 1);
        put(&mut f, 56, 4096);
        put(&mut f, 60, END_OF_CHAIN);
        put(&mut f, 68, END_OF_CHAIN);
        put(&mut f, 76, 0);
        for k in 1..HEADER_DIFAT {
            put(&mut f, 76 + 4 * k, FREE);
        }
        let fat = 512;
        for k in 0..128 {
            let next = match k {
                0 => 0xFFFF_FFFD,
                1 | 10 => END_OF_CHAIN,
                2..=9 => k as u32 + 1,
                _ => FREE,
            };
            put(&mut f, fat + 4 * k, next);
        }
        let entry = |f: &mut Vec<u8>, index: usize, name: &str, kind: u8, start: u32, size: u64| {
            let at = 1024 + index * ENTRY_LEN;
            let units: Vec<u8> = name
                .encode_utf16()
                .chain([0])
                .flat_map(u16::to_le_bytes)
                .collect();
            f[at..at + units.len()].copy_from_slice(&units);
            f[at + 64..at + 66].copy_from_slice(&(units.len() as u16).to_le_bytes());
            f[at + 66] = kind;
            f[at + 116..at + 120].copy_from_slice(&start.to_le_bytes());
            f[at + 120..at + 128].copy_from_slice(&size.to_le_bytes());
        };
        entry(&mut f, 0, "Root Entry", ROOT, END_OF_CHAIN, 0);
        entry(&mut f, 1, "A", STREAM, 2, 4600);
        let content: Vec<u8> = (0..4600u32).map(|k| (k % 251) as u8).collect();
        f[1536..1536 + 4600].copy_from_slice(&content);
        (f, content)
    }

    #[test]
    fn a_stream_is_read_along_its_chain() {
        let (f, content) = file();
        let compound = Compound::open(&f, Format::Mnt).unwrap();
        assert_eq!(compound.stream("A").unwrap(), content);
        let err = compound.stream("B").unwrap_err().to_string();
        assert!(err.contains("no stream \"B\""), "{err}");
    }

    #[test]
    fn loops_and_sectors_outside_the_file_are_errors() {
        let (mut f, _) = file();
        // sector 10 points back to 2: the chain never ends
        f[512 + 40..512 + 44].copy_from_slice(&2u32.to_le_bytes());
        let err = Compound::open(&f, Format::Mnt)
            .unwrap()
            .stream("A")
            .unwrap_err();
        assert!(err.to_string().contains("loops"), "{err}");
        let (mut f, _) = file();
        f[512 + 12..512 + 16].copy_from_slice(&4000u32.to_le_bytes());
        let err = Compound::open(&f, Format::Mnt)
            .unwrap()
            .stream("A")
            .unwrap_err();
        assert!(err.to_string().contains("sector 4000"), "{err}");
        let (mut f, _) = file();
        f[44..48].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(Compound::open(&f, Format::Mnt).is_err());
        assert!(Compound::open(&f[..100], Format::Mnt).is_err());
    }
}
