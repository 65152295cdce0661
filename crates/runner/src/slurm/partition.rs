//! Whether a job's request fits a node of its partition, checked before
//! submission. Slurm accepts a job that asks for more CPUs or memory than
//! any node of the partition has, then keeps it pending for ever with
//! `Reason=PartitionConfig`; the submitter would wait without a word. The
//! nodes are read from `sinfo -h -N -o '%P %c %m'` (one line per node and
//! partition: name, with `*` on the default; CPUs; memory in MB; see
//! sinfo(1), "-o <output_format>").

use std::collections::BTreeMap;
use std::process::Command;

use super::settings::JobResources;

/// The CPUs and memory of every node of one partition.
#[derive(Clone, Debug, PartialEq)]
pub struct PartitionNodes {
    pub partition: String,
    /// (CPUs, memory in MB) per node.
    pub nodes: Vec<(u32, u64)>,
}

impl PartitionNodes {
    /// Whether some node holds `cpus` and `mem_mb` together. A node whose
    /// memory Slurm does not know (`1`, its default for RealMemory) is not
    /// held to a memory request: Slurm does not track it there either.
    pub fn holds(&self, cpus: u32, mem_mb: u64) -> bool {
        self.nodes
            .iter()
            .any(|&(c, m)| c >= cpus && (m <= 1 || m >= mem_mb))
    }

    /// The most CPUs and memory any node has (not necessarily one node).
    pub fn largest(&self) -> (u32, u64) {
        let cpus = self.nodes.iter().map(|n| n.0).max().unwrap_or(0);
        let mem_mb = self.nodes.iter().map(|n| n.1).max().unwrap_or(0);
        (cpus, mem_mb)
    }
}

/// The nodes of `partition` (the default partition for `None`) in `sinfo
/// -h -N -o '%P %c %m'` output; `None` when it lists none. Values Slurm
/// marks as a minimum (`2+`) count as that minimum.
pub fn parse_sinfo(text: &str, partition: Option<&str>) -> Option<PartitionNodes> {
    let mut found: BTreeMap<String, Vec<(u32, u64)>> = BTreeMap::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let (Some(name), Some(cpus), Some(mem)) = (words.next(), words.next(), words.next()) else {
            continue;
        };
        let is_default = name.ends_with('*');
        let name = name.trim_end_matches('*');
        let wanted = match partition {
            Some(p) => p == name,
            None => is_default,
        };
        let number = |w: &str| w.trim_end_matches('+').parse::<u64>().ok();
        if let (true, Some(cpus), Some(mem_mb)) = (wanted, number(cpus), number(mem)) {
            let cpus = u32::try_from(cpus).unwrap_or(u32::MAX);
            found
                .entry(name.to_owned())
                .or_default()
                .push((cpus, mem_mb));
        }
    }
    let (partition, nodes) = found.into_iter().next()?;
    Some(PartitionNodes { partition, nodes })
}

/// The nodes of `partition` as `sinfo` reports them now; `None` when
/// `sinfo` cannot be run or lists nothing (then `sbatch` is left to judge).
pub fn query(partition: Option<&str>) -> Option<PartitionNodes> {
    let mut cmd = Command::new("sinfo");
    cmd.args(["-h", "-N", "-o", "%P %c %m"]);
    if let Some(p) = partition {
        cmd.arg(format!("--partition={p}"));
    }
    let out = cmd.output().ok().filter(|o| o.status.success())?;
    parse_sinfo(&String::from_utf8_lossy(&out.stdout), partition)
}

/// The refusal of a request no node of `nodes` can hold, naming the stage,
/// the request, the nodes' limits and the profile's `limits:`.
pub fn refusal(stage: &str, kind: &str, asked: &JobResources, nodes: &PartitionNodes) -> String {
    let (cpus, mem_mb) = nodes.largest();
    format!(
        "stage `{stage}` ({kind}) asks for {} CPUs and {} MB, but no node of the Slurm \
         partition `{}` holds that (its nodes have at most {cpus} CPUs and {mem_mb} MB): the job \
         would wait in the queue for ever (Reason=PartitionConfig). Lower the requests in the \
         Slurm site profile, e.g. `limits: {{ cpus: {cpus}, mem: {mem_mb}M }}`",
        asked.cpus, asked.mem_mb, nodes.partition
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    // What `sinfo -h -N -o '%P %c %m'` printed on a two-partition site.
    const SINFO: &str = "\
debug* 2 3900
debug* 4+ 7800
long 16 64000
";

    #[test]
    fn the_default_or_named_partition_is_read_from_sinfo() {
        let debug = parse_sinfo(SINFO, None).unwrap();
        assert_eq!(debug.partition, "debug");
        assert_eq!(debug.nodes, [(2, 3900), (4, 7800)]);
        assert_eq!(debug.largest(), (4, 7800));
        // The `dic` kind's 4 CPUs / 8 GB fit no debug node, but the long ones.
        assert!(!debug.holds(4, 8192));
        assert!(debug.holds(4, 7800) && !debug.holds(5, 100));
        let long = parse_sinfo(SINFO, Some("long")).unwrap();
        assert!(long.holds(4, 8192));
        assert_eq!(parse_sinfo(SINFO, Some("gpu")), None);
        assert_eq!(parse_sinfo("garbage\n\n", None), None);
    }

    #[test]
    fn a_node_without_known_memory_is_held_to_cpus_only() {
        let nodes = parse_sinfo("hctest* 2 1\n", None).unwrap();
        assert!(nodes.holds(2, 8192) && !nodes.holds(4, 1));
    }

    #[test]
    fn the_refusal_names_stage_request_partition_and_limits() {
        let nodes = parse_sinfo("hctest* 2 1024\n", None).unwrap();
        let asked = JobResources {
            cpus: 4,
            mem_mb: 8192,
            time_min: 60,
            partition: None,
            account: None,
        };
        let e = refusal("ut-dic", "dic", &asked, &nodes);
        for part in [
            "stage `ut-dic` (dic)",
            "4 CPUs and 8192 MB",
            "`hctest`",
            "at most 2 CPUs and 1024 MB",
            "limits: { cpus: 2, mem: 1024M }",
        ] {
            assert!(e.contains(part), "{part}: {e}");
        }
    }
}
