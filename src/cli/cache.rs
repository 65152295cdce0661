//! `hypercontact cache ls | verify | gc | clean`: inspect and prune the
//! cache folder of a pipeline (or any cache folder).

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use anyhow::{Context as _, Result, bail};
use hypercontact_core::Registry;
use hypercontact_runner::cache::{Cache, EntryInfo, EntryState, not_a_cache};
use hypercontact_runner::exec::default_cache_dir;
use hypercontact_runner::producer;
use hypercontact_runner::{Pipeline, Plan, PlanOptions};

use super::args::{CacheAction, CacheWhere};

pub fn cache_command(action: CacheAction, registry: &Registry) -> Result<()> {
    match action {
        CacheAction::Ls { at } => ls(&cache_dir(&at, registry)?),
        CacheAction::Gc {
            at,
            keep,
            older_than_days,
        } => gc(&cache_dir(&at, registry)?, &keep, older_than_days, registry),
        CacheAction::Verify {
            at,
            producer: false,
        } => verify(&cache_dir(&at, registry)?),
        CacheAction::Verify { at, producer: true } => other_producers(&cache_dir(&at, registry)?),
        CacheAction::Clean { at } => clean(&cache_dir(&at, registry)?),
    }
}

fn cache_dir(at: &CacheWhere, registry: &Registry) -> Result<PathBuf> {
    Ok(match (&at.cache, &at.pipeline) {
        (Some(dir), _) => dir.clone(),
        (None, Some(p)) => default_cache_dir(&Pipeline::load(p, registry)?),
        (None, None) => Path::new("pipelines").join(".hypercontact").join("cache"),
    })
}

/// The cache in `dir`, or `None` once the user is told there is none
/// (`then`: what that means for the command, after the folder's name).
fn open_or_say(dir: &Path, then: &str) -> std::io::Result<Option<Cache>> {
    let cache = Cache::open_existing(dir)?;
    if cache.is_none() {
        say!("no cache at {}{then}", dir.display());
    }
    Ok(cache)
}

/// One line per entry: key, kind, stage, size, producer, last use; then
/// the total.
fn ls(dir: &Path) -> Result<()> {
    let Some(cache) = open_or_say(dir, "").with_context(|| format!("opening {}", dir.display()))?
    else {
        return Ok(());
    };
    let entries = cache.list()?;
    let mut total = 0;
    for e in &entries {
        total += e.bytes;
        let (kind, stage, made_by) = e.manifest.as_ref().map_or(("(unreadable)", "", ""), |m| {
            (
                m.kind.as_str(),
                m.stage.as_str(),
                producer::shown(m.producer.as_deref()),
            )
        });
        say!(
            "{}  {:<16} {:<16} {:>10}  {:<26} {}",
            &e.key,
            kind,
            stage,
            human_bytes(e.bytes),
            made_by,
            e.last_used.map_or("-".into(), ago)
        );
    }
    say!(
        "{} entries, {} in {}",
        entries.len(),
        human_bytes(total),
        dir.display()
    );
    Ok(())
}

/// Removes the entries the `keep` pipelines do not use (with any), those
/// unused for longer than the age limit, the unreadable ones, and the
/// debris of interrupted runs.
fn gc(
    dir: &Path,
    keep: &[PathBuf],
    older_than_days: Option<f64>,
    registry: &Registry,
) -> Result<()> {
    let Some(cache) = open_or_say(dir, ": nothing to remove")? else {
        return Ok(());
    };
    let keys = kept_keys(&cache, keep, registry)?;
    let max_age = match (older_than_days, keep.is_empty()) {
        (Some(d), _) => Some(Duration::from_secs_f64(d * 86_400.0)),
        (None, true) => Some(Duration::from_secs(30 * 86_400)),
        (None, false) => None,
    };
    let mut removed = 0;
    let mut freed = 0;
    for e in cache.list()? {
        let unused = !keep.is_empty() && !keys.contains(&e.key);
        if unused || unused_for_longer(&e, max_age) || e.manifest.is_none() {
            cache.remove(&e.key)?;
            removed += 1;
            freed += e.bytes;
        }
    }
    let debris = cache.clean_debris()?;
    say!(
        "removed {removed} entries ({}) and {debris} leftovers of interrupted runs",
        human_bytes(freed)
    );
    Ok(())
}

/// Every entry key the plans of these pipelines use now.
fn kept_keys(cache: &Cache, keep: &[PathBuf], registry: &Registry) -> Result<HashSet<String>> {
    let mut keys = HashSet::new();
    for p in keep {
        let pipeline = Pipeline::load(p, registry)?;
        let plan = Plan::build(&pipeline, cache, &PlanOptions::default(), None)?;
        keys.extend(plan.stages.into_iter().map(|s| s.key));
    }
    Ok(keys)
}

/// The entry was last used longer ago than `max_age` (never, without one).
fn unused_for_longer(entry: &EntryInfo, max_age: Option<Duration>) -> bool {
    match (max_age, entry.last_used) {
        (Some(age), Some(t)) => SystemTime::now().duration_since(t).unwrap_or_default() > age,
        _ => false,
    }
}

/// Lists each corrupt entry; fails if there is any.
fn verify(dir: &Path) -> Result<()> {
    let Some(cache) = open_or_say(dir, "")? else {
        return Ok(());
    };
    let entries = cache.list()?;
    let mut corrupt = 0;
    for e in &entries {
        match cache.verify(&e.key) {
            EntryState::Valid(_) => {}
            EntryState::Corrupt(why) => {
                corrupt += 1;
                say!("corrupt  {}  {why}", e.key);
            }
            // Removed by a concurrent `gc` or a dropped temporary.
            EntryState::Missing => {}
        }
    }
    say!(
        "{} entries checked, {corrupt} corrupt, in {}",
        entries.len(),
        dir.display()
    );
    if corrupt > 0 {
        bail!("{corrupt} corrupt cache entries in {}", dir.display());
    }
    Ok(())
}

/// Lists the entries whose manifest names another build than this one
/// (#31, 4): their key holds no trace of the code, so a stage whose
/// `version` was not bumped would reuse them. Exit 0: a listing, not a
/// failure; `gc` or `clean` removes them if wanted.
fn other_producers(dir: &Path) -> Result<()> {
    let Some(cache) = open_or_say(dir, "")? else {
        return Ok(());
    };
    let entries = cache.list()?;
    let running = producer::running();
    let mut other = 0;
    for e in &entries {
        let Some(m) = &e.manifest else {
            continue;
        };
        if m.producer.as_deref() != Some(running) {
            other += 1;
            say!(
                "{}  {:<16} {:<16} made by {}",
                e.key,
                m.kind,
                m.stage,
                producer::shown(m.producer.as_deref())
            );
        }
    }
    say!(
        "{} entries, {other} made by another build than this one (see --version), in {}",
        entries.len(),
        dir.display()
    );
    Ok(())
}

fn clean(dir: &Path) -> Result<()> {
    if let Some(why) = not_a_cache(dir)? {
        bail!("{}: {why}", dir.display());
    }
    if !dir.exists() {
        say!("no cache at {}", dir.display());
        return Ok(());
    }
    Cache::open(dir)?.clean()?;
    say!("removed {}", dir.display());
    Ok(())
}

fn human_bytes(n: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = n as f64;
    let mut u = 0;
    while v >= 1024.0 && u < UNITS.len() - 1 {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{n} B")
    } else {
        format!("{v:.1} {}", UNITS[u])
    }
}

fn ago(t: SystemTime) -> String {
    let s = SystemTime::now()
        .duration_since(t)
        .unwrap_or_default()
        .as_secs();
    match s {
        0..=119 => format!("{s} s ago"),
        120..=7199 => format!("{} min ago", s / 60),
        7200..=172_799 => format!("{} h ago", s / 3600),
        _ => format!("{} days ago", s / 86_400),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_in_binary_units() {
        assert_eq!(human_bytes(0), "0 B");
        assert_eq!(human_bytes(1023), "1023 B");
        assert_eq!(human_bytes(1024), "1.0 KiB");
        assert_eq!(human_bytes(1536), "1.5 KiB");
        assert_eq!(human_bytes(5 << 30), "5.0 GiB");
        // Past TiB the unit stays TiB.
        assert_eq!(human_bytes(1 << 50), "1024.0 TiB");
    }

    #[test]
    fn ages_switch_unit_where_the_number_would_grow_long() {
        let before = |s: u64| SystemTime::now() - Duration::from_secs(s);
        assert_eq!(ago(before(5)), "5 s ago");
        assert_eq!(ago(before(600)), "10 min ago");
        assert_eq!(ago(before(3 * 3600)), "3 h ago");
        assert_eq!(ago(before(5 * 86_400)), "5 days ago");
        // A clock set back: a last use in the future reads as now.
        assert_eq!(ago(SystemTime::now() + Duration::from_secs(60)), "0 s ago");
    }
}
