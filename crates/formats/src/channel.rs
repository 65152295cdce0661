//! Which channel of a multi-channel file is read, and how the channels
//! found are reported.
//!
//! AFM files hold several images of one scan (trace and retrace, height,
//! deflection, phase); the default is the channel SurfaceTopography reads
//! by default (its channel index 0 among the channels it lists), so a map
//! read without a choice equals its reference. The metadata of every map
//! says which channel was read (`channel`) and lists the channels found
//! (`channels`, `index: name` joined by `; `).

use crate::{Format, FormatError, Topography};

/// A channel of a file, chosen by position or by name.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub enum Channel {
    /// the format's default: the height channel SurfaceTopography reads first
    #[default]
    Default,
    /// the channel at this position in the list the metadata key `channels` shows
    Index(usize),
    /// the first channel of this name (compared without regard to case)
    Name(String),
}

impl std::fmt::Display for Channel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Channel::Default => write!(f, "the default channel"),
            Channel::Index(index) => write!(f, "channel {index}"),
            Channel::Name(name) => write!(f, "channel {name:?}"),
        }
    }
}

/// The channels of a file as the metadata shows them: `0: Height; 1: Phase`.
pub(crate) fn list(names: &[String]) -> String {
    let entries: Vec<String> = names
        .iter()
        .enumerate()
        .map(|(index, name)| format!("{index}: {name}"))
        .collect();
    entries.join("; ")
}

/// The index of the channel `asked` names among `names`, `default` for
/// [`Channel::Default`]; an error listing the channels when there is none.
pub(crate) fn pick(
    format: Format,
    names: &[String],
    default: usize,
    asked: &Channel,
) -> Result<usize, FormatError> {
    let found = match asked {
        Channel::Default => (default < names.len()).then_some(default),
        Channel::Index(index) => (*index < names.len()).then_some(*index),
        Channel::Name(name) => names
            .iter()
            .position(|candidate| candidate.eq_ignore_ascii_case(name.trim())),
    };
    found.ok_or_else(|| FormatError::NoSuchChannel {
        format: format.name(),
        message: if names.is_empty() {
            format!("{asked} was asked for, but the file holds no channel read here")
        } else {
            format!(
                "{asked} was asked for, but the file holds {} channel{}: {}",
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                list(names)
            )
        },
    })
}

/// Checks the choice for a single-channel format whose one channel is `name`.
pub(crate) fn single(format: Format, name: &str, asked: &Channel) -> Result<(), FormatError> {
    pick(format, &[name.to_string()], 0, asked).map(|_| ())
}

/// `map` with the metadata of a single-channel file: its channel `name`.
pub(crate) fn named(map: Topography, name: &str) -> Topography {
    with_channels(map, &[name.to_string()], 0)
}

/// `map` with the metadata `channel` (the one read, `index` of `names`)
/// and `channels` (all of them) put first.
pub(crate) fn with_channels(mut map: Topography, names: &[String], index: usize) -> Topography {
    let mut metadata = vec![
        (
            "channel".to_string(),
            names.get(index).cloned().unwrap_or_default(),
        ),
        ("channels".to_string(), list(names)),
    ];
    metadata.append(&mut map.metadata);
    map.metadata = metadata;
    map
}

/// What an unknown file is, for the error: the format its signature
/// names, else whether it reads as text, and its first bytes in hex (at
/// most 8). Never the file's text: a message must not echo a file's
/// contents (a credentials file given as a height map, issue #50).
pub(crate) fn describe_start(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "an empty file".into();
    }
    let shown: Vec<String> = bytes.iter().take(8).map(|b| format!("{b:02x}")).collect();
    let shown = shown.join(" ");
    // files users mistake for height maps, by their magic numbers
    let kinds: [(&[u8], &str); 9] = [
        (b"\x89PNG\r\n\x1a\n", "a PNG image"),
        (b"\xff\xd8\xff", "a JPEG image"),
        (b"GIF8", "a GIF image"),
        (b"%PDF", "a PDF document"),
        (b"\x1f\x8b", "gzip-compressed data"),
        (b"PK\x03\x04", "a zip archive without an X3P's main.xml"),
        (b"II*\0", "a TIFF image"),
        (b"<?xml", "an XML document"),
        (b"\x7fELF", "an executable (ELF)"),
    ];
    if let Some((_, kind)) = kinds.iter().find(|(magic, _)| bytes.starts_with(magic)) {
        return format!("{kind} (first bytes {shown})");
    }
    // UTF-8 text without control characters, a character cut at the end
    // of the sample allowed.
    let head = &bytes[..bytes.len().min(512)];
    let valid = match std::str::from_utf8(head) {
        Ok(text) => Some(text),
        Err(e) if e.error_len().is_none() => std::str::from_utf8(&head[..e.valid_up_to()]).ok(),
        Err(_) => None,
    };
    let is_text = valid.is_some_and(|t| {
        t.chars()
            .all(|c| !c.is_control() || c == '\t' || c == '\r' || c == '\n')
    });
    match is_text {
        true => format!("text (first bytes {shown})"),
        false => format!("first bytes {shown}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        ["Height", "Height", "Phase"].map(String::from).to_vec()
    }

    #[test]
    fn channels_are_picked_by_index_or_name() {
        let names = names();
        let f = Format::Nanoscope;
        assert_eq!(pick(f, &names, 0, &Channel::Default).unwrap(), 0);
        assert_eq!(pick(f, &names, 0, &Channel::Index(1)).unwrap(), 1);
        assert_eq!(
            pick(f, &names, 0, &Channel::Name("phase".into())).unwrap(),
            2
        );
        // a repeated name is its first channel
        assert_eq!(
            pick(f, &names, 0, &Channel::Name("Height".into())).unwrap(),
            0
        );
    }

    #[test]
    fn a_missing_channel_lists_those_found() {
        let err = pick(Format::Nanoscope, &names(), 0, &Channel::Index(3)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "Bruker Nanoscope .di: channel 3 was asked for, but the file holds 3 channels: \
             0: Height; 1: Height; 2: Phase"
        );
        let err = pick(Format::Tmd, &[], 0, &Channel::Default).unwrap_err();
        assert!(err.to_string().contains("no channel read here"), "{err}");
        assert!(single(Format::Tmd, "Default", &Channel::Name("x".into())).is_err());
        assert!(single(Format::Tmd, "Default", &Channel::Index(0)).is_ok());
    }

    #[test]
    fn unknown_files_are_described_by_their_start() {
        assert_eq!(describe_start(b""), "an empty file");
        // Text is named as text, never shown (issue #50).
        assert_eq!(
            describe_start(b"root:SECRET:19000:0:99999:7:::\nmore"),
            "text (first bytes 72 6f 6f 74 3a 53 45 43)"
        );
        assert_eq!(describe_start(&[0, 1, 2]), "first bytes 00 01 02");
        assert_eq!(
            describe_start(b"\x89PNG\r\n\x1a\n\0\0"),
            "a PNG image (first bytes 89 50 4e 47 0d 0a 1a 0a)"
        );
    }
}
