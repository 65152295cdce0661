//! What a stage job asks Slurm for, and where it comes from: the stage
//! kind's declaration ([`hypercontact_core::Resources`]), the pipeline's
//! `slurm:` key (every stage), the stage's own `slurm:` key; partition,
//! account and setup lines also from the site profile.
//!
//! Memory and time are read in Slurm's own notation (`sbatch(1)`: `--mem`
//! in megabytes unless suffixed K, M, G or T, each 1024 times the last;
//! `--time` as minutes, `MM:SS`, `HH:MM:SS`, `D-HH`, `D-HH:MM` or
//! `D-HH:MM:SS`), so a line copied from a site's batch script works here.

use std::path::{Path, PathBuf};

use hypercontact_core::Resources;
use hypercontact_core::regular_file::{MIB, read_checked_text};
use serde::Deserialize;

use crate::error::PipelineError;
use crate::yaml::Located;

/// A `slurm:` key of a pipeline (pipeline-wide or one stage's).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SlurmKeys {
    pub partition: Option<Name>,
    pub account: Option<Name>,
    pub cpus: Option<Cpus>,
    pub mem: Option<MemoryMb>,
    pub time: Option<TimeMin>,
}

/// A partition or account name: letters, digits, `_ - . ,` (a partition
/// list is comma-separated).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(try_from = "String")]
pub struct Name(pub String);

impl TryFrom<String> for Name {
    type Error = String;
    fn try_from(text: String) -> Result<Self, String> {
        if !text.is_empty()
            && text
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.,".contains(c))
        {
            Ok(Name(text))
        } else {
            Err(format!(
                "`{text}` is not a Slurm name (letters, digits, `_ - . ,`)"
            ))
        }
    }
}

/// CPUs per task, 1 … 4096.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(try_from = "serde_json::Value")]
pub struct Cpus(pub u32);

impl TryFrom<serde_json::Value> for Cpus {
    type Error = String;
    fn try_from(value: serde_json::Value) -> Result<Self, String> {
        match value.as_u64() {
            Some(n @ 1..=4096) => Ok(Cpus(n as u32)),
            _ => Err(format!("{value} is not a count of CPUs from 1 to 4096")),
        }
    }
}

/// Memory per job in MiB (`--mem`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(try_from = "serde_json::Value")]
pub struct MemoryMb(pub u64);

impl TryFrom<serde_json::Value> for MemoryMb {
    type Error = String;
    fn try_from(value: serde_json::Value) -> Result<Self, String> {
        let text = scalar_text(value, "an amount of memory")?;
        parse_memory_mb(&text).map(MemoryMb).ok_or_else(|| {
            format!("`{text}` is not an amount of memory (Slurm's notation: 4096, 500M, 4G)")
        })
    }
}

/// A time limit in whole minutes (`--time`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(try_from = "serde_json::Value")]
pub struct TimeMin(pub u64);

impl TryFrom<serde_json::Value> for TimeMin {
    type Error = String;
    fn try_from(value: serde_json::Value) -> Result<Self, String> {
        let text = scalar_text(value, "a time limit")?;
        parse_time_min(&text).map(TimeMin).ok_or_else(|| {
            format!(
                "`{text}` is not a time limit (Slurm's notation: minutes, MM:SS, HH:MM:SS, \
                 D-HH, D-HH:MM or D-HH:MM:SS)"
            )
        })
    }
}

/// A number or text as the text Slurm would read (`4096`, `4G`, `1:00:00`);
/// anything else is not `what`.
fn scalar_text(value: serde_json::Value, what: &str) -> Result<String, String> {
    match value {
        serde_json::Value::String(s) => Ok(s),
        serde_json::Value::Number(n) => Ok(n.to_string()),
        other => Err(format!("{other} is not {what}")),
    }
}

/// `4096`, `500M`, `4G`, `1.5G`, `2T`, `800K` → MiB, rounded up; `None` for
/// anything else or zero.
pub fn parse_memory_mb(text: &str) -> Option<u64> {
    let t = text.trim();
    let (number, scale) = match t.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => {
            let scale = match c.to_ascii_uppercase() {
                'K' => 1.0 / 1024.0,
                'M' => 1.0,
                'G' => 1024.0,
                'T' => 1024.0 * 1024.0,
                _ => return None,
            };
            (&t[..i], scale)
        }
        _ => (t, 1.0),
    };
    if number.is_empty() || !number.chars().all(|c| c.is_ascii_digit() || c == '.') {
        return None;
    }
    let value: f64 = number.parse().ok()?;
    let mb = (value * scale).ceil();
    (1.0..1e12).contains(&mb).then_some(mb as u64)
}

/// Slurm's time formats → whole minutes, rounded up; `None` for anything
/// else or zero.
pub fn parse_time_min(text: &str) -> Option<u64> {
    let t = text.trim();
    let number = |s: &str| -> Option<u64> {
        (!s.is_empty() && s.len() <= 9 && s.chars().all(|c| c.is_ascii_digit()))
            .then(|| s.parse().ok())
            .flatten()
    };
    let seconds = match t.split_once('-') {
        Some((days, rest)) => {
            let days = number(days)?;
            let parts: Vec<u64> = rest.split(':').map(number).collect::<Option<_>>()?;
            let (h, m, s) = match parts.as_slice() {
                [h] => (*h, 0, 0),
                [h, m] => (*h, *m, 0),
                [h, m, s] => (*h, *m, *s),
                _ => return None,
            };
            ((days * 24 + h) * 60 + m) * 60 + s
        }
        None => {
            let parts: Vec<u64> = t.split(':').map(number).collect::<Option<_>>()?;
            match parts.as_slice() {
                [m] => m * 60,
                [m, s] => m * 60 + s,
                [h, m, s] => (h * 60 + m) * 60 + s,
                _ => return None,
            }
        }
    };
    let minutes = seconds.div_ceil(60);
    (minutes > 0).then_some(minutes)
}

/// The site's side of a Slurm run: read from `--slurm-profile FILE`, else
/// `$HYPERCONTACT_SLURM_PROFILE`, else `~/.config/hypercontact/slurm.yaml`
/// when it exists.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SiteProfile {
    pub partition: Option<Name>,
    pub account: Option<Name>,
    /// Shell lines run in every job before the stage (`module load …`).
    pub setup: Vec<String>,
    /// More `sbatch` options, one per item (`--qos=normal`).
    pub sbatch_args: Vec<String>,
    /// The `hypercontact` the jobs run [default: this very binary]; on a
    /// cluster, a path every node sees.
    pub command: Option<PathBuf>,
    /// Seconds between two looks at the queue [default 5].
    pub poll_s: Option<f64>,
    /// The most a job may ask for here (`cpus`, `mem`, `time`): what the
    /// site's nodes and partition allow. Every request above is lowered to
    /// it, so a kind declared for 4 CPUs still runs on 2-core nodes rather
    /// than waiting in the queue for ever.
    pub limits: Limits,
}

/// Upper bounds of a job's resources.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Limits {
    pub cpus: Option<Cpus>,
    pub mem: Option<MemoryMb>,
    pub time: Option<TimeMin>,
}

/// What a YAML value that is not a map is, for the refusal.
fn yaml_kind(value: &serde_json::Value) -> &'static str {
    match value {
        serde_json::Value::Array(_) => "a list",
        serde_json::Value::String(_) => "a text",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::Bool(_) => "a yes/no value",
        serde_json::Value::Null | serde_json::Value::Object(_) => "nothing usable",
    }
}

impl SiteProfile {
    /// Reads and checks a profile file; errors name the file and line.
    pub fn load(path: &Path) -> Result<Self, PipelineError> {
        let text = read_checked_text(path, "Slurm site profiles", MIB).map_err(|e| {
            PipelineError::new(
                path,
                format!("cannot read the Slurm site profile: it {}", e.why),
            )
        })?;
        let doc =
            Located::parse(&text).map_err(|e| PipelineError::new(path, e.message).located(e.at))?;
        if doc.value.is_null() {
            return Ok(Self::default());
        }
        // A list would be read by position, its items reported as keys `0`, `1`.
        if !doc.value.is_object() {
            return Err(PipelineError::new(
                path,
                format!(
                    "the Slurm site profile must be a map of settings (partition:, limits:, ...); \
                     found {}",
                    yaml_kind(&doc.value)
                ),
            )
            .located(doc.locate::<&str>(&[])));
        }
        let profile: SiteProfile =
            crate::pipeline::located_deserialize(path, &doc, doc.value.clone())?;
        if let Some(p) = profile.poll_s
            && !(0.05..=3600.0).contains(&p)
        {
            return Err(
                PipelineError::new(path, format!("poll_s: {p} s is outside 0.05 … 3600"))
                    .located(doc.locate(&["poll_s"])),
            );
        }
        for (i, line) in profile.setup.iter().enumerate() {
            if line.contains('\n') {
                return Err(PipelineError::new(
                    path,
                    "setup: one shell line per item (this one holds a line break)",
                )
                .located(doc.locate(&["setup", &i.to_string()])));
            }
        }
        Ok(profile)
    }

    /// The profile a run uses: `explicit`, else the environment's, else the
    /// user's default file if there is one, else none.
    pub fn find(explicit: Option<&Path>) -> Result<Self, PipelineError> {
        if let Some(path) = explicit {
            return Self::load(path);
        }
        if let Some(path) = std::env::var_os("HYPERCONTACT_SLURM_PROFILE") {
            return Self::load(Path::new(&path));
        }
        let config = std::env::var_os("XDG_CONFIG_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")));
        match config.map(|c| c.join("hypercontact").join("slurm.yaml")) {
            Some(path) if path.is_file() => Self::load(&path),
            _ => Ok(Self::default()),
        }
    }
}

/// What one job asks for, all sources resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct JobResources {
    pub cpus: u32,
    pub mem_mb: u64,
    pub time_min: u64,
    pub partition: Option<String>,
    pub account: Option<String>,
}

impl JobResources {
    /// Declaration, then the profile, the pipeline-wide key, the stage's key
    /// (later wins).
    pub fn resolve(
        declared: Resources,
        profile: &SiteProfile,
        pipeline: &SlurmKeys,
        stage: &SlurmKeys,
    ) -> Self {
        let mut r = JobResources {
            cpus: declared.cpus,
            mem_mb: declared.mem_mb,
            time_min: declared.time_min,
            partition: profile.partition.as_ref().map(|n| n.0.clone()),
            account: profile.account.as_ref().map(|n| n.0.clone()),
        };
        for keys in [pipeline, stage] {
            if let Some(p) = &keys.partition {
                r.partition = Some(p.0.clone());
            }
            if let Some(a) = &keys.account {
                r.account = Some(a.0.clone());
            }
            if let Some(c) = keys.cpus {
                r.cpus = c.0;
            }
            if let Some(m) = keys.mem {
                r.mem_mb = m.0;
            }
            if let Some(t) = keys.time {
                r.time_min = t.0;
            }
        }
        let limits = &profile.limits;
        if let Some(c) = limits.cpus {
            r.cpus = r.cpus.min(c.0);
        }
        if let Some(m) = limits.mem {
            r.mem_mb = r.mem_mb.min(m.0);
        }
        if let Some(t) = limits.time {
            r.time_min = r.time_min.min(t.0);
        }
        r
    }

    /// The `sbatch` options for these resources.
    pub fn sbatch_args(&self) -> Vec<String> {
        let mut args = vec![
            format!("--cpus-per-task={}", self.cpus),
            format!("--mem={}M", self.mem_mb),
            format!("--time={}", self.time_min),
        ];
        if let Some(p) = &self.partition {
            args.push(format!("--partition={p}"));
        }
        if let Some(a) = &self.account {
            args.push(format!("--account={a}"));
        }
        args
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_in_slurm_notation() {
        for (text, mb) in [
            ("4096", 4096),
            ("500M", 500),
            ("4G", 4096),
            ("4g", 4096),
            ("1.5G", 1536),
            ("2T", 2 * 1024 * 1024),
            ("800K", 1),
            ("1", 1),
        ] {
            assert_eq!(parse_memory_mb(text), Some(mb), "{text}");
        }
        for bad in ["", "0", "G", "4X", "-1G", "4 GB", "1e3", "nan", "0.0M"] {
            assert_eq!(parse_memory_mb(bad), None, "{bad}");
        }
    }

    #[test]
    fn time_in_slurm_notation() {
        for (text, min) in [
            ("30", 30),
            ("30:00", 30),
            ("30:01", 31),
            ("01:00:00", 60),
            ("1-0", 1440),
            ("1-2", 1560),
            ("1-02:30", 1590),
            ("0-00:00:30", 1),
            ("2-00:00:00", 2880),
        ] {
            assert_eq!(parse_time_min(text), Some(min), "{text}");
        }
        for bad in [
            "",
            "0",
            "00:00",
            "1:2:3:4",
            "a",
            "1-",
            "-5",
            "1-2:3:4:5",
            "1.5",
            "x-1",
        ] {
            assert_eq!(parse_time_min(bad), None, "{bad}");
        }
    }

    #[test]
    fn later_sources_win() {
        let declared = Resources {
            cpus: 4,
            mem_mb: 8192,
            time_min: 120,
        };
        let profile = SiteProfile {
            partition: Some(Name("compute".into())),
            account: Some(Name("lab".into())),
            ..SiteProfile::default()
        };
        let pipeline = SlurmKeys {
            partition: Some(Name("short".into())),
            mem: Some(MemoryMb(1024)),
            ..SlurmKeys::default()
        };
        let stage = SlurmKeys {
            cpus: Some(Cpus(1)),
            time: Some(TimeMin(5)),
            ..SlurmKeys::default()
        };
        let r = JobResources::resolve(declared, &profile, &pipeline, &stage);
        assert_eq!(
            r,
            JobResources {
                cpus: 1,
                mem_mb: 1024,
                time_min: 5,
                partition: Some("short".into()),
                account: Some("lab".into()),
            }
        );
        assert_eq!(
            r.sbatch_args(),
            [
                "--cpus-per-task=1",
                "--mem=1024M",
                "--time=5",
                "--partition=short",
                "--account=lab"
            ]
        );
        let r = JobResources::resolve(
            declared,
            &SiteProfile::default(),
            &SlurmKeys::default(),
            &SlurmKeys::default(),
        );
        assert_eq!((r.cpus, r.mem_mb, r.time_min), (4, 8192, 120));
        assert_eq!(r.partition, None);
        // The site's limits lower every request above them, whatever its
        // source, and leave the others.
        let capped = SiteProfile {
            limits: Limits {
                cpus: Some(Cpus(2)),
                mem: Some(MemoryMb(4096)),
                time: None,
            },
            ..SiteProfile::default()
        };
        let stage = SlurmKeys {
            cpus: Some(Cpus(16)),
            ..SlurmKeys::default()
        };
        let r = JobResources::resolve(declared, &capped, &SlurmKeys::default(), &stage);
        assert_eq!((r.cpus, r.mem_mb, r.time_min), (2, 4096, 120));
    }

    #[test]
    fn the_shipped_example_profile_reads() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/slurm/site.yaml");
        let p = SiteProfile::load(&path).unwrap();
        assert_eq!(p.partition, Some(Name("compute".into())));
        assert_eq!(p.setup.len(), 2);
        assert_eq!(p.limits.mem, Some(MemoryMb(64 * 1024)));
        assert_eq!(p.limits.time, Some(TimeMin(2 * 24 * 60)));
        assert_eq!(p.poll_s, Some(10.0));
    }

    #[test]
    fn a_bad_profile_is_refused_with_its_line() {
        let t = tempfile::tempdir().unwrap();
        let path = t.path().join("site.yaml");
        for (text, says) in [
            (
                "partition: a\nlimit: { cpus: 2 }\n",
                "2:1: unknown field `limit`",
            ),
            (
                "limits:\n  mem: lots\n",
                "`lots` is not an amount of memory",
            ),
            ("poll_s: 0\n", "1:1: poll_s: 0 s is outside"),
            (
                "setup:\n  - \"module load x\\nrm -rf /\"\n",
                "2:5: setup: one shell line",
            ),
        ] {
            std::fs::write(&path, text).unwrap();
            let e = SiteProfile::load(&path).unwrap_err().to_string();
            assert!(e.contains("site.yaml") && e.contains(says), "{e}");
        }
        let e = SiteProfile::load(&t.path().join("none.yaml")).unwrap_err();
        assert!(e.to_string().contains("cannot read the Slurm site profile"));
    }

    // Before, a list was read by position: its first item was reported as
    // a setting named `0`.
    #[test]
    fn a_profile_that_is_not_a_map_is_refused_as_such() {
        let t = tempfile::tempdir().unwrap();
        let path = t.path().join("site.yaml");
        for (text, found) in [
            (
                "- partition: compute\n- limits: { cpus: 2 }\n",
                "found a list",
            ),
            ("compute\n", "found a text"),
        ] {
            std::fs::write(&path, text).unwrap();
            let e = SiteProfile::load(&path).unwrap_err().to_string();
            assert!(
                e.contains("must be a map of settings") && e.contains(found),
                "{e}"
            );
            assert!(!e.contains("`0`"), "{e}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]

        /// Any text: an answer or a refusal, never a panic; every written
        /// form of a duration reads back as its minutes, rounded up.
        #[test]
        fn time_and_memory_never_panic_and_read_back(
            text in "\\PC{0,24}",
            d in 0u64..30, h in 0u64..24, m in 0u64..60, sec in 0u64..60,
        ) {
            let _ = parse_time_min(&text);
            let _ = parse_memory_mb(&text);
            let seconds = ((d * 24 + h) * 60 + m) * 60 + sec;
            let want = (seconds > 0).then(|| seconds.div_ceil(60));
            proptest::prop_assert_eq!(parse_time_min(&format!("{d}-{h:02}:{m:02}:{sec:02}")), want);
            if d == 0 {
                proptest::prop_assert_eq!(parse_time_min(&format!("{h}:{m:02}:{sec:02}")), want);
            }
        }

        /// Any bytes as a profile file: a profile or an error naming the
        /// file, never a panic.
        #[test]
        fn any_profile_bytes_are_read_or_refused(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..200)) {
            let t = tempfile::tempdir().unwrap();
            let path = t.path().join("site.yaml");
            std::fs::write(&path, &bytes).unwrap();
            if let Err(e) = SiteProfile::load(&path) {
                proptest::prop_assert!(e.to_string().contains("site.yaml"));
            }
        }
    }
}
