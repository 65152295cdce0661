//! The Slurm executor against a real single-node Slurm started here: Debian's
//! `munged`, `slurmctld` and `slurmd` on a localhost configuration written
//! by the test, stopped by PID at the end. `pipelines/quick.yaml` and the
//! study of `pipelines/demo.yaml` must give the local executor's bytes,
//! with one job per entry; a job cancelled mid-stage leaves no corrupt
//! entry and a rerun completes; a failed job is named with its id and log;
//! Ctrl-C cancels the submitted jobs; `--detach` and `status` follow them.
//!
//! Without Slurm on the machine the test says so and returns; under CI
//! (`CI` set, as `.ci/run` does, which installs Slurm) that is a failure.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, products, text};

fn pipeline(name: &str) -> PathBuf {
    common::repo().join("pipelines").join(name)
}

const DAEMONS: [&str; 3] = ["munged", "slurmctld", "slurmd"];
const CLIENTS: [&str; 4] = ["sbatch", "squeue", "scancel", "sinfo"];

/// Where a program is on PATH (or in the sbin folders daemons live in).
fn which(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin"].map(PathBuf::from))
        .map(|dir| dir.join(program))
        .find(|p| p.is_file())
}

/// A free TCP port on loopback (bound, read, released).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// A one-node Slurm cluster in a temporary folder.
struct Cluster {
    dir: tempfile::TempDir,
    conf: PathBuf,
    daemons: Vec<(String, Child)>,
}

impl Cluster {
    /// Starts munge, the controller and the node daemon, or says why it
    /// cannot (`None`: not on this machine).
    fn start() -> Option<Cluster> {
        let missing: Vec<&str> = DAEMONS
            .iter()
            .chain(CLIENTS.iter())
            .copied()
            .filter(|p| which(p).is_none())
            .collect();
        let uid = Command::new("id").arg("-u").output().ok().map(|o| o.stdout);
        let why = if !missing.is_empty() {
            Some(format!(
                "Slurm is not installed here (missing: {}; Debian: apt-get install slurmctld \
                 slurmd slurm-client munge)",
                missing.join(", ")
            ))
        } else if uid.as_deref() != Some(b"0\n") {
            Some("slurmd must run as root to start jobs, and this test is not root".into())
        } else {
            None
        };
        if let Some(why) = why {
            assert!(
                std::env::var_os("CI").is_none(),
                "CI must exercise the Slurm executor, but {why}; .ci/run installs it"
            );
            eprintln!("SKIPPED: the Slurm executor test: {why}");
            return None;
        }

        let dir = tempfile::Builder::new()
            .prefix("hc-slurm")
            .tempdir()
            .unwrap();
        let d = dir.path();
        let munge = d.join("munge");
        std::fs::create_dir(&munge).unwrap();
        std::fs::create_dir(d.join("state")).unwrap();
        std::fs::create_dir(d.join("spool")).unwrap();
        set_mode(&munge, 0o755);
        let key = munge.join("munge.key");
        // A fresh key: 1024 bytes from a fixed-seed sequence is enough for a
        // cluster that lives for one test on loopback.
        let mut state = 0x2545_f491_4f6c_dd1d_u64 ^ u64::from(std::process::id());
        let bytes: Vec<u8> = (0..1024)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 24) as u8
            })
            .collect();
        std::fs::write(&key, bytes).unwrap();
        set_mode(&key, 0o600);

        let host = String::from_utf8(Command::new("hostname").output().unwrap().stdout)
            .unwrap()
            .trim()
            .to_owned();
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let socket = munge.join("munge.socket");
        let conf = d.join("slurm.conf");
        let p = |name: &str| d.join(name).display().to_string();
        let text = format!(
            "# A one-node cluster on loopback for the hypercontact tests.\n\
             ClusterName=hctest\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmUser=root\n\
             SlurmdUser=root\n\
             SlurmctldPort={ctld}\n\
             SlurmdPort={slurmd}\n\
             AuthType=auth/munge\n\
             AuthInfo=socket={socket}\n\
             StateSaveLocation={state}\n\
             SlurmdSpoolDir={spool}\n\
             SlurmctldPidFile={ctld_pid}\n\
             SlurmdPidFile={slurmd_pid}\n\
             SlurmctldLogFile={ctld_log}\n\
             SlurmdLogFile={slurmd_log}\n\
             PlugStackConfig={plugstack}\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             JobCompType=jobcomp/none\n\
             SchedulerType=sched/builtin\n\
             SchedulerParameters=batch_sched_delay=0,sched_min_interval=0\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU_Memory\n\
             ReturnToService=2\n\
             MpiDefault=none\n\
             SwitchType=switch/none\n\
             NodeName=hcnode NodeHostname={host} NodeAddr=127.0.0.1 CPUs={cpus} \
             RealMemory=1024 State=UNKNOWN\n\
             PartitionName=hctest Nodes=hcnode Default=YES MaxTime=INFINITE State=UP\n",
            ctld = free_port(),
            slurmd = free_port(),
            socket = socket.display(),
            state = p("state"),
            spool = p("spool"),
            ctld_pid = p("slurmctld.pid"),
            slurmd_pid = p("slurmd.pid"),
            ctld_log = p("slurmctld.log"),
            slurmd_log = p("slurmd.log"),
            plugstack = p("plugstack.conf"),
        );
        std::fs::write(&conf, text).unwrap();
        std::fs::write(d.join("plugstack.conf"), "").unwrap();

        let mut cluster = Cluster {
            conf: conf.clone(),
            daemons: Vec::new(),
            dir,
        };
        cluster.spawn(
            "munged",
            Command::new(which("munged").unwrap()).args([
                "-F".to_owned(),
                "--force".to_owned(),
                format!("--key-file={}", key.display()),
                format!("--socket={}", socket.display()),
                format!("--pid-file={}", munge.join("munged.pid").display()),
                format!("--log-file={}", munge.join("munged.log").display()),
                format!("--seed-file={}", munge.join("munged.seed").display()),
            ]),
        );
        cluster.wait_for("munge's socket", || socket.exists());
        cluster.spawn(
            "slurmctld",
            Command::new(which("slurmctld").unwrap())
                .args(["-D", "-f"])
                .arg(&conf),
        );
        cluster.spawn(
            "slurmd",
            Command::new(which("slurmd").unwrap())
                .args(["-D", "-N", "hcnode", "-f"])
                .arg(&conf),
        );
        cluster.wait_for("the node to be idle", || {
            cluster
                .client("sinfo")
                .args(["--noheader", "--format=%T"])
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        });
        Some(cluster)
    }

    fn spawn(&mut self, name: &str, command: &mut Command) {
        let log = std::fs::File::create(self.dir.path().join(format!("{name}.out"))).unwrap();
        let child = command
            .env("SLURM_CONF", &self.conf)
            .stdin(Stdio::null())
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .spawn()
            .unwrap_or_else(|e| panic!("starting {name}: {e}"));
        self.daemons.push((name.to_owned(), child));
    }

    fn wait_for(&self, what: &str, mut ready: impl FnMut() -> bool) {
        let t0 = Instant::now();
        while !ready() {
            if t0.elapsed() > Duration::from_secs(60) {
                panic!("waited 60 s for {what}; logs:\n{}", self.logs());
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    fn logs(&self) -> String {
        let mut out = String::new();
        for name in [
            "munged.out",
            "slurmctld.out",
            "slurmd.out",
            "slurmctld.log",
            "slurmd.log",
        ] {
            let text = std::fs::read_to_string(self.dir.path().join(name)).unwrap_or_default();
            let lines: Vec<&str> = text.lines().collect();
            out.push_str(&format!("== {name}\n"));
            for l in &lines[lines.len().saturating_sub(20)..] {
                out.push_str(l);
                out.push('\n');
            }
        }
        out
    }

    /// A Slurm client command talking to this cluster.
    fn client(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.env("SLURM_CONF", &self.conf);
        c
    }

    /// `hypercontact` talking to this cluster.
    fn hypercontact(&self) -> Command {
        let mut c = bin();
        c.env("SLURM_CONF", &self.conf);
        c
    }

    /// Job id → state of every job the controller knows.
    fn states(&self) -> BTreeMap<String, String> {
        let o = self
            .client("squeue")
            .args(["--noheader", "--states=all", "--format=%i %T"])
            .output()
            .unwrap();
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter_map(|l| {
                let (id, state) = l.trim().split_once(' ')?;
                Some((id.to_owned(), state.to_owned()))
            })
            .collect()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        // No job outlives the cluster, then each daemon by its PID: TERM,
        // then KILL if it does not go.
        let _ = self.client("scancel").arg("--user=root").output();
        for (_, child) in self.daemons.iter_mut().rev() {
            let _ = Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .output();
            let t0 = Instant::now();
            while t0.elapsed() < Duration::from_secs(10) {
                if let Ok(Some(_)) = child.try_wait() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn set_mode(path: &Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// The Slurm run's products are the local run's, byte for byte; the runs'
/// own records (`provenance.json`, `study.json`: times and folders) and
/// the Slurm folder aside.
fn assert_same_products(local: &Path, slurm: &Path) {
    let skip =
        |name: &str| common::run_record(name) || name == "study.json" || name.starts_with("slurm/");
    let a = products(local, skip);
    let b = products(slurm, skip);
    assert!(!a.is_empty());
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        b.keys().collect::<Vec<_>>(),
        "the same files"
    );
    for (rel, bytes) in &a {
        assert!(bytes == &b[rel], "{rel} differs from the local run");
    }
}

fn submission(out: &Path) -> serde_json::Value {
    let path = out.join("slurm").join("submission.json");
    serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap()
}

fn jobs(out: &Path) -> Vec<serde_json::Value> {
    submission(out)["jobs"].as_array().unwrap().clone()
}

#[test]
fn the_slurm_executor_gives_the_local_bytes_with_one_job_per_entry() {
    let Some(cluster) = Cluster::start() else {
        return;
    };
    let t = tempfile::tempdir().unwrap();
    let profile = t.path().join("site.yaml");
    // A 1-CPU, 256 MiB job fits the test node whatever the kind declares.
    std::fs::write(
        &profile,
        "poll_s: 0.2\nsetup:\n  - echo site setup ran\nlimits: { cpus: 1, mem: 256M }\n",
    )
    .unwrap();
    let run = |what: &str, pipeline: &str, cache: &str, out: &str, extra: &[&str]| {
        let mut c = cluster.hypercontact();
        c.arg(what)
            .arg(self::pipeline(pipeline))
            .arg("--quiet")
            .arg("--cache")
            .arg(t.path().join(cache))
            .arg("--out")
            .arg(t.path().join(out))
            .args(extra);
        c
    };
    let slurm = ["--executor", "slurm", "--slurm-profile"];
    let slurm: Vec<&str> = slurm
        .into_iter()
        .chain([profile.to_str().unwrap()])
        .collect();
    // The Slurm arguments and more.
    let on_slurm = |extra: &[&'static str]| {
        let mut args = slurm.clone();
        args.extend_from_slice(extra);
        args
    };

    // 1. The quick pipeline, locally and through Slurm, on separate caches.
    let t0 = Instant::now();
    let local = run("run", "quick.yaml", "local-cache", "local", &[])
        .output()
        .unwrap();
    assert!(local.status.success(), "{}", text(&local));
    let local_s = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let out = run("run", "quick.yaml", "slurm-cache", "slurm", &slurm)
        .output()
        .unwrap();
    let slurm_s = t0.elapsed().as_secs_f64();
    assert!(out.status.success(), "{}\n{}", text(&out), cluster.logs());
    assert_same_products(&t.path().join("local"), &t.path().join("slurm"));
    let quick_jobs = jobs(&t.path().join("slurm"));
    let provenance: serde_json::Value = serde_json::from_slice(
        &std::fs::read(t.path().join("slurm").join("provenance.json")).unwrap(),
    )
    .unwrap();
    let stages = provenance["stages"].as_object().unwrap();
    // Every stage was a job (temporary ones too), each entry once.
    assert_eq!(quick_jobs.len(), stages.len());
    let keys: std::collections::BTreeSet<&str> = quick_jobs
        .iter()
        .map(|j| j["key"].as_str().unwrap())
        .collect();
    assert_eq!(keys.len(), quick_jobs.len());
    for (name, record) in stages {
        let job = record["job"].as_str().unwrap_or_default();
        assert!(job.starts_with("slurm "), "{name}: {record}");
        assert_eq!(record["cache"], "miss", "{name}");
    }
    for job in &quick_jobs {
        let log = std::fs::read_to_string(job["log"].as_str().unwrap()).unwrap();
        assert!(log.contains("site setup ran"), "{log}");
        assert!(log.contains("computed stage"), "{log}");
        // The dependencies are the plan's edges: a stage waits for the jobs
        // of exactly the stages it reads.
        assert_eq!(job["cpus"], 1);
    }
    let fit = quick_jobs.iter().find(|j| j["stage"] == "fit").unwrap();
    let id = |stage: &str| {
        quick_jobs.iter().find(|j| j["stage"] == stage).unwrap()["job_id"]
            .as_str()
            .unwrap()
            .to_owned()
    };
    let mut after: Vec<String> = fit["after"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_owned())
        .collect();
    after.sort();
    let mut expected = vec![id("ut-dic"), id("pt-dic"), id("bt-dic")];
    expected.sort();
    assert_eq!(after, expected);
    // The longest chain of dependent jobs: each link waits for a pass of
    // the scheduler.
    let mut depth: BTreeMap<&str, usize> = BTreeMap::new();
    for job in &quick_jobs {
        let d = job["after"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| depth[a.as_str().unwrap()])
            .max()
            .map_or(1, |d| d + 1);
        depth.insert(job["job_id"].as_str().unwrap(), d);
    }
    let longest = depth.values().max().copied().unwrap_or(0);
    eprintln!(
        "quick: {} stage jobs through Slurm in {slurm_s:.1} s, locally {local_s:.1} s: \
         {:.2} s more per job, {:.2} s more per link of the longest chain ({longest} jobs)",
        quick_jobs.len(),
        (slurm_s - local_s) / quick_jobs.len() as f64,
        (slurm_s - local_s) / longest as f64
    );

    // 2. A rerun submits nothing and exports the same bytes.
    let again = run("run", "quick.yaml", "slurm-cache", "slurm-again", &slurm)
        .output()
        .unwrap();
    assert!(again.status.success(), "{}", text(&again));
    assert!(jobs(&t.path().join("slurm-again")).is_empty());
    assert_same_products(&t.path().join("local"), &t.path().join("slurm-again"));

    // 3. The demo study: shared upstream entries once, the gathered table
    //    and every variant's outputs as the local study's.
    let local = run("study", "demo.yaml", "local-cache", "study-local", &[])
        .output()
        .unwrap();
    assert!(local.status.success(), "{}", text(&local));
    let out = run("study", "demo.yaml", "slurm-cache", "study-slurm", &slurm)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}\n{}", text(&out), cluster.logs());
    assert_same_products(&t.path().join("study-local"), &t.path().join("study-slurm"));
    let study_jobs = jobs(&t.path().join("study-slurm"));
    // 2 × 2 variants: surf, epdm once; trunc per level (2); contact per
    // variant (4); contact-linear per level (2).
    let mut per_stage: BTreeMap<&str, usize> = BTreeMap::new();
    for j in &study_jobs {
        *per_stage.entry(j["stage"].as_str().unwrap()).or_default() += 1;
        let log = std::fs::read_to_string(j["log"].as_str().unwrap()).unwrap();
        assert!(
            log.contains("computed stage"),
            "each entry computed once: {log}"
        );
    }
    assert_eq!(
        per_stage,
        BTreeMap::from([
            ("contact", 4),
            ("contact-linear", 2),
            ("epdm", 1),
            ("surf", 1),
            ("trunc", 2)
        ])
    );
    let study = |dir: &str| -> serde_json::Value {
        let mut v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(t.path().join(dir).join("study.json")).unwrap())
                .unwrap();
        for variant in v.as_array_mut().unwrap() {
            variant.as_object_mut().unwrap().remove("out_dir");
        }
        v
    };
    // Also what each variant computed and reused, as the local study says.
    assert_eq!(study("study-local"), study("study-slurm"));

    // 4. A job cancelled mid-stage: the fit with a long bootstrap, alone.
    let set = ["--set", "fit.bootstrap.count=2500", "--only", "fit"];
    let args = on_slurm(&set);
    let submitter = run("run", "quick.yaml", "slurm-cache", "cancelled", &args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let sub_path = t.path().join("cancelled/slurm/submission.json");
    let t0 = Instant::now();
    let (job_id, log, key) = loop {
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "{}",
            cluster.logs()
        );
        if sub_path.exists() {
            let job = jobs(&t.path().join("cancelled"))[0].clone();
            let log = PathBuf::from(job["log"].as_str().unwrap());
            let id = job["job_id"].as_str().unwrap().to_owned();
            if cluster.states().get(&id).is_some_and(|s| s == "RUNNING")
                && std::fs::read_to_string(&log).is_ok_and(|l| l.contains("stage `fit`"))
            {
                break (id, log, job["key"].as_str().unwrap().to_owned());
            }
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    // Well into the computation (the refits take seconds on one CPU).
    std::thread::sleep(Duration::from_millis(800));
    let o = cluster.client("scancel").arg(&job_id).output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let o = submitter.wait_with_output().unwrap();
    assert!(!o.status.success(), "a cancelled job fails the run");
    let message = text(&o);
    assert!(
        message.contains("stage `fit` (material-fit) failed in Slurm job")
            && message.contains(&job_id)
            && message.contains("CANCELLED")
            && message.contains(&log.display().to_string()),
        "{message}"
    );
    let log_text = std::fs::read_to_string(&log).unwrap();
    assert!(
        !log_text.contains("computed stage"),
        "cancelled before the end: {log_text}"
    );
    let cache = t.path().join("slurm-cache");
    assert!(!cache.join("entries").join(&key).exists(), "no entry");
    let verify = bin()
        .args(["cache", "verify", "--cache"])
        .arg(&cache)
        .output()
        .unwrap();
    assert!(verify.status.success(), "{}", text(&verify));
    assert!(text(&verify).contains(", 0 corrupt"), "{}", text(&verify));
    // The rerun submits only the missing entry and gives the local bytes.
    let rerun = run("run", "quick.yaml", "slurm-cache", "cancelled", &args)
        .output()
        .unwrap();
    assert!(rerun.status.success(), "{}", text(&rerun));
    assert_eq!(jobs(&t.path().join("cancelled")).len(), 1);
    let local = run("run", "quick.yaml", "local-cache", "cancelled-local", &set)
        .output()
        .unwrap();
    assert!(local.status.success(), "{}", text(&local));
    assert_same_products(
        &t.path().join("cancelled-local"),
        &t.path().join("cancelled"),
    );

    // 5. A stage that fails: named with its job and log, the error in the
    //    log's tail; what does not depend on it still runs.
    let bad = t.path().join("bad");
    std::fs::create_dir(&bad).unwrap();
    std::fs::write(bad.join("broken.npy"), b"\x93NUMPY garbage").unwrap();
    let bad_pipeline = bad.join("bad.yaml");
    std::fs::write(
        &bad_pipeline,
        "name: bad\nstages:\n  surf:\n    uses: height-map\n    with: { path: broken.npy, \
         pixel_m: 1.0e-6 }\n  trunc:\n    uses: truncation\n    inputs: { surface: surf }\n  \
         epdm:\n    uses: material-preset\n    with: { name: paper-epdm }\n",
    )
    .unwrap();
    let o = cluster
        .hypercontact()
        .arg("run")
        .arg(&bad_pipeline)
        .args(["--quiet", "--cache"])
        .arg(bad.join("cache"))
        .arg("--out")
        .arg(bad.join("out"))
        .args(&slurm)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let message = text(&o);
    let bad_jobs = jobs(&bad.join("out"));
    let surf = bad_jobs.iter().find(|j| j["stage"] == "surf").unwrap();
    assert!(
        message.contains(&format!(
            "stage `surf` (height-map) failed in Slurm job {} (FAILED); log: {}",
            surf["job_id"].as_str().unwrap(),
            surf["log"].as_str().unwrap()
        )),
        "{message}"
    );
    assert!(
        message.contains("broken.npy"),
        "the stage's error: {message}"
    );
    assert!(
        message.contains("not run, as a stage they read failed: trunc"),
        "{message}"
    );
    let epdm = bad_jobs.iter().find(|j| j["stage"] == "epdm").unwrap();
    assert!(
        bad.join("cache/entries")
            .join(epdm["key"].as_str().unwrap())
            .exists(),
        "an independent stage still ran"
    );

    // 6. Ctrl-C while waiting cancels what was submitted.
    let submitter = run(
        "run",
        "demo.yaml",
        "slurm-cache",
        "interrupted",
        &on_slurm(&["--set", "trunc.levels=400"]),
    )
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    let sub_path = t.path().join("interrupted/slurm/submission.json");
    let t0 = Instant::now();
    while !sub_path.exists() {
        assert!(t0.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = Command::new("kill")
        .args(["-INT", &submitter.id().to_string()])
        .output()
        .unwrap();
    assert!(o.status.success());
    let o = submitter.wait_with_output().unwrap();
    assert!(!o.status.success());
    assert!(
        text(&o).contains("cancelled: scancel sent to"),
        "{}",
        text(&o)
    );
    let states = cluster.states();
    for job in jobs(&t.path().join("interrupted")) {
        let id = job["job_id"].as_str().unwrap();
        let state = states.get(id).map_or("gone", String::as_str);
        assert!(
            matches!(state, "CANCELLED" | "COMPLETED" | "gone"),
            "job {id} of stage {} is {state} after Ctrl-C",
            job["stage"]
        );
    }

    // 7. --detach returns with the jobs queued; status follows them; the
    //    same command again collects the outputs without resubmitting.
    let args = on_slurm(&["--set", "trunc.levels=300", "--detach"]);
    let o = run("run", "demo.yaml", "slurm-cache", "detached", &args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(!t.path().join("detached/provenance.json").exists());
    let detached = jobs(&t.path().join("detached"));
    assert_eq!(detached.len(), 3, "trunc, contact, contact-linear");
    let t0 = Instant::now();
    loop {
        let o = bin()
            .arg("status")
            .arg(pipeline("demo.yaml"))
            .arg("--out")
            .arg(t.path().join("detached"))
            .env("SLURM_CONF", &cluster.conf)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let said = text(&o);
        for job in &detached {
            assert!(said.contains(job["job_id"].as_str().unwrap()), "{said}");
        }
        if said.contains("all entries are in the cache") {
            break;
        }
        assert!(t0.elapsed() < Duration::from_secs(120), "{said}");
        std::thread::sleep(Duration::from_millis(300));
    }
    let args = on_slurm(&["--set", "trunc.levels=300"]);
    let o = run("run", "demo.yaml", "slurm-cache", "detached", &args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(jobs(&t.path().join("detached")).is_empty());
    assert!(t.path().join("detached/contact/response.parquet").exists());
}

/// Without `limits:`, the `dic` kind's 4 CPUs / 8 GB fit no node of the
/// one-node test partition (1024 MB): before, the job was submitted and
/// pended for ever (Reason=PartitionConfig) while the submitter waited
/// without a word. Now the run fails before submitting anything, naming the
/// stage, its request, the partition's limits and the profile's `limits:`.
#[test]
fn a_request_no_node_can_hold_fails_before_submission() {
    let Some(cluster) = Cluster::start() else {
        return;
    };
    let t = tempfile::tempdir().unwrap();
    let profile = t.path().join("site.yaml");
    std::fs::write(&profile, "poll_s: 0.2\n").unwrap();
    let started = Instant::now();
    let mut run = cluster.hypercontact();
    run.arg("run")
        .arg(pipeline("quick.yaml"))
        .arg("--quiet")
        .arg("--cache")
        .arg(t.path().join("cache"))
        .arg("--out")
        .arg(t.path().join("out"))
        .args(["--executor", "slurm", "--slurm-profile"])
        .arg(&profile)
        .stdin(Stdio::null());
    let mut child = run
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // A regression waits for ever: kill it after a minute and fail.
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("still waiting after 60 s for a job no node can hold");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(status.code(), Some(1), "{stderr}");
    for part in [
        "stage `",
        "CPUs and",
        "no node of the Slurm partition `hctest`",
        "Reason=PartitionConfig",
        "limits:",
    ] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    // Nothing was submitted: no submission record, no job in the queue.
    assert!(!t.path().join("out/slurm/submission.json").exists());
    let queue = cluster
        .client("squeue")
        .args(["-h", "-o", "%i"])
        .output()
        .unwrap();
    assert!(queue.stdout.trim_ascii().is_empty(), "{}", text(&queue));
}
