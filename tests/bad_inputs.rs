//! The bad-input catalog of issue #12: every input the fault campaign fed the
//! release binary, each pinned to the message `hypercontact` prints for it.
//!
//! A case is a few files written into a fresh folder (a pipeline, a CSV,
//! `.npy` bytes, images), the command line, and the exit status it must end
//! with: 1 for a refused input (a panic, 101, or an abort by signal fails the
//! case by name), 2 where clap refuses an argument before the program runs,
//! 0 for the few inputs that must simply not crash. Each case is one snapshot,
//! `tests/snapshots/bad_inputs__<case>.snap`: the command and its input files,
//! then how the process ended and what it printed, with the folder written
//! `<dir>`, so a reviewer reads input and message together.
//!
//! Beyond the snapshot every refusal is held to the issue's bar: an
//! `error:` line that names what the case says it must (file, line, stage,
//! parameter), no empty name (``` `` ```), no cause printed twice, and none
//! of a case's known misleading wordings.

use std::path::Path;
use std::process::{Command, ExitStatus};

/// A command line to run in a fresh folder, with the files it needs.
struct Case {
    /// `<dir>` in an argument stands for the case's folder.
    args: Vec<String>,
    files: Vec<(String, Vec<u8>)>,
    /// Commands that must succeed first (to fill a cache, say).
    before: Vec<Vec<String>>,
    /// The folder (under the case's) the command runs in.
    cwd: Option<&'static str>,
    exit: i32,
    /// Folders made read-only before the command runs.
    read_only: Vec<&'static str>,
    /// Paths (under the case's folder) that must not exist afterwards.
    absent: Vec<&'static str>,
    /// Text the output must hold exactly once.
    once: Vec<&'static str>,
    /// What the message must name (file, line, stage, parameter).
    mentions: Vec<&'static str>,
    /// Text the message must not hold (a misleading cause).
    lacks: Vec<&'static str>,
    /// Named pipes (FIFOs) made under the case's folder: nothing ever
    /// writes to them, so a reader that opens one hangs.
    fifos: Vec<&'static str>,
    /// Symlinks made under the case's folder: (link, target), `<dir>` in
    /// the target standing for the case's folder.
    symlinks: Vec<(&'static str, &'static str)>,
    /// Sparse files: (name, size in bytes), holes after the file's written
    /// content if `file` gave it some (a real header, say), else all holes.
    sparse: Vec<(&'static str, u64)>,
}

impl Case {
    fn new(args: &[&str]) -> Self {
        Self {
            args: args.iter().map(|a| a.to_string()).collect(),
            files: Vec::new(),
            before: Vec::new(),
            cwd: None,
            exit: 1,
            read_only: Vec::new(),
            absent: Vec::new(),
            once: Vec::new(),
            mentions: Vec::new(),
            lacks: Vec::new(),
            fifos: Vec::new(),
            symlinks: Vec::new(),
            sparse: Vec::new(),
        }
    }

    /// `hypercontact run <dir>/p.yaml` into `<dir>/out` with its own cache,
    /// quiet (no timings), plus `extra`.
    fn run(pipeline: &str, extra: &[&str]) -> Self {
        Self::command("run", pipeline, extra)
    }

    /// The same for `hypercontact study`.
    fn study(pipeline: &str, extra: &[&str]) -> Self {
        Self::command("study", pipeline, extra)
    }

    fn command(verb: &str, pipeline: &str, extra: &[&str]) -> Self {
        let mut args = vec![
            verb,
            "<dir>/p.yaml",
            "--out",
            "<dir>/out",
            "--cache",
            "<dir>/cache",
            "-q",
        ];
        args.extend_from_slice(extra);
        Self::new(&args).file("p.yaml", pipeline)
    }

    fn file(mut self, name: &str, content: impl AsRef<[u8]>) -> Self {
        self.files
            .push((name.to_owned(), content.as_ref().to_vec()));
        self
    }

    fn before(mut self, args: &[&str]) -> Self {
        self.before
            .push(args.iter().map(|a| a.to_string()).collect());
        self
    }

    fn exit(mut self, code: i32) -> Self {
        self.exit = code;
        self
    }

    fn cwd(mut self, dir: &'static str) -> Self {
        self.cwd = Some(dir);
        self
    }

    fn read_only(mut self, dir: &'static str) -> Self {
        self.read_only.push(dir);
        self
    }

    fn absent(mut self, path: &'static str) -> Self {
        self.absent.push(path);
        self
    }

    fn once(mut self, text: &'static str) -> Self {
        self.once.push(text);
        self
    }

    fn mentions(mut self, texts: &[&'static str]) -> Self {
        self.mentions.extend_from_slice(texts);
        self
    }

    fn lacks(mut self, text: &'static str) -> Self {
        self.lacks.push(text);
        self
    }

    fn fifo(mut self, name: &'static str) -> Self {
        self.fifos.push(name);
        self
    }

    fn symlink(mut self, link: &'static str, target: &'static str) -> Self {
        self.symlinks.push((link, target));
        self
    }

    fn sparse(mut self, name: &'static str, bytes: u64) -> Self {
        self.sparse.push((name, bytes));
        self
    }
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_hypercontact"));
    // The panic message without a backtrace, whatever the caller's setting.
    c.env("RUST_BACKTRACE", "0");
    c
}

fn args_in(args: &[String], dir: &Path) -> Vec<String> {
    args.iter()
        .map(|a| a.replace("<dir>", &dir.display().to_string()))
        .collect()
}

/// How the process ended, as a reviewer wants to read it.
fn ending(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(101), _) => "exit 101 (panic)".into(),
        (Some(code), _) => format!("exit {code}"),
        (None, Some(6)) => "killed by signal 6 (abort)".into(),
        (None, Some(signal)) => format!("killed by signal {signal}"),
        (None, None) => "unknown ending".into(),
    }
}

/// The output with everything that differs from run to run or machine to
/// machine replaced: the case's folder, the panicking thread's id, where
/// cargo keeps the crates' sources, and cache keys.
fn normalise(text: &str, dir: &Path) -> String {
    let mut text = text.replace(&dir.display().to_string(), "<dir>");
    if let Ok(real) = dir.canonicalize() {
        text = text.replace(&real.display().to_string(), "<dir>");
    }
    // `panicked at /home/x/.cargo/registry/src/index.crates.io-…/nalgebra-0.34.2/…`
    text = text
        .lines()
        .map(
            |line| match (line.find(" at /"), line.find("/registry/src/")) {
                (Some(at), Some(registry)) if at < registry => {
                    let rest = &line[registry + "/registry/src/".len()..];
                    let krate = rest.find('/').map_or(rest, |slash| &rest[slash + 1..]);
                    format!("{} at <registry>/{krate}\n", &line[..at])
                }
                _ => format!("{line}\n"),
            },
        )
        .collect::<String>();
    // Rust ≥ 1.89 prints `thread 'main' (12345) panicked at`.
    let mut from = 0;
    while let Some(found) = text[from..].find("thread 'main' (") {
        let open = from + found + "thread 'main' (".len();
        let digits = text[open..].bytes().take_while(u8::is_ascii_digit).count();
        if digits > 0 {
            text.replace_range(open..open + digits, "<tid>");
        }
        from = open;
    }
    text.split_inclusive(|c: char| !c.is_ascii_alphanumeric())
        .map(|word| {
            let (body, tail) = word.split_at(
                word.trim_end_matches(|c: char| !c.is_ascii_alphanumeric())
                    .len(),
            );
            let is_key = body.len() == 12
                && body
                    .bytes()
                    .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
                && body.bytes().any(|b| b.is_ascii_digit());
            if is_key {
                format!("<key>{tail}")
            } else {
                word.to_owned()
            }
        })
        .collect()
}

/// The command and its input files, heading the snapshot: text (up to 24
/// lines), binary by size.
fn describe(case: &Case) -> String {
    let mut out = format!("$ hypercontact {}\n", case.args.join(" "));
    for b in &case.before {
        out.push_str(&format!("(after `hypercontact {}`)\n", b.join(" ")));
    }
    for name in &case.fifos {
        out.push_str(&format!(
            "--- {name}: a named pipe (FIFO) nothing writes to\n"
        ));
    }
    for (link, target) in &case.symlinks {
        out.push_str(&format!("--- {link} -> {target}\n"));
    }
    for (name, bytes) in &case.sparse {
        out.push_str(&format!(
            "--- {name}: {bytes} bytes, sparse (holes after any content below)\n"
        ));
    }
    for (name, bytes) in &case.files {
        match std::str::from_utf8(bytes) {
            Ok(text) if !text.contains('\0') => {
                out.push_str(&format!("--- {name}\n"));
                let lines: Vec<&str> = text.lines().collect();
                for line in lines.iter().take(24) {
                    out.push_str(&format!("{line}\n"));
                }
                if lines.len() > 24 {
                    out.push_str(&format!("… ({} lines in all)\n", lines.len()));
                } else if !text.is_empty() && !text.ends_with('\n') {
                    out.push_str("⏎ (no final newline)\n");
                }
            }
            _ => {
                out.push_str(&format!("--- {name}: {} bytes", bytes.len()));
                if let Some(header) = npy_header(bytes) {
                    out.push_str(&format!(", header {header}"));
                }
                out.push('\n');
            }
        }
    }
    out
}

/// The header of a `.npy` file, if `bytes` start like one.
fn npy_header(bytes: &[u8]) -> Option<String> {
    let rest = bytes.strip_prefix(b"\x93NUMPY\x01\x00")?;
    let len = usize::from(u16::from_le_bytes([*rest.first()?, *rest.get(1)?]));
    let header = rest.get(2..2 + len)?;
    Some(String::from_utf8_lossy(header).trim_end().to_owned())
}

/// Whether the current user can write into a read-only folder (root can).
fn writes_despite_mode(dir: &Path) -> bool {
    let probe = dir.join(".probe");
    let wrote = std::fs::write(&probe, b"").is_ok();
    let _ = std::fs::remove_file(probe);
    wrote
}

fn set_mode(dir: &Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(dir, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// Runs `case` and checks it: the snapshot, then the exit status and the
/// message's shape.
fn check(name: &str, case: Case) {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    for (file, bytes) in &case.files {
        let path = dir.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    }
    make_special_files(&case, dir);
    let cwd = case.cwd.map_or(dir.to_path_buf(), |c| dir.join(c));
    std::fs::create_dir_all(&cwd).unwrap();
    for before in &case.before {
        let o = bin()
            .args(args_in(before, dir))
            .current_dir(&cwd)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "case `{name}`: the preparing command `{}` failed:\n{}",
            before.join(" "),
            String::from_utf8_lossy(&o.stderr)
        );
    }
    for ro in &case.read_only {
        let path = dir.join(ro);
        std::fs::create_dir_all(&path).unwrap();
        set_mode(&path, 0o555);
        if writes_despite_mode(&path) {
            set_mode(&path, 0o755);
            eprintln!("case `{name}` skipped: this user writes into read-only folders (root)");
            return;
        }
    }
    let mut command = bin();
    command.args(args_in(&case.args, dir)).current_dir(&cwd);
    let output = output_within(command, name, CASE_LIMITS);
    for ro in &case.read_only {
        set_mode(&dir.join(ro), 0o755);
    }
    let stdout = normalise(&String::from_utf8_lossy(&output.stdout), dir);
    let stderr = normalise(&String::from_utf8_lossy(&output.stderr), dir);
    let ended = ending(output.status);
    let mut shown = format!("{}=== {ended}\n--- stderr\n{stderr}", describe(&case));
    if !stdout.is_empty() {
        shown.push_str(&format!("--- stdout\n{stdout}"));
    }
    insta::with_settings!({ omit_expression => true }, {
        insta::assert_snapshot!(name, shown);
    });

    assert_eq!(
        output.status.code(),
        Some(case.exit),
        "case `{name}`: expected exit {}, got {ended}:\n{stderr}{stdout}",
        case.exit
    );
    assert!(
        !stderr.contains("``"),
        "case `{name}`: an empty name (of a stage, a parameter, a column):\n{stderr}"
    );
    if case.exit == 1 {
        assert!(
            stderr.starts_with("error: "),
            "case `{name}`: no `error:` message:\n{stderr}"
        );
        assert_eq!(
            repeated_cause(&stderr),
            None,
            "case `{name}`: a cause is printed twice:\n{stderr}"
        );
    }
    for text in &case.mentions {
        assert!(
            stderr.contains(text),
            "case `{name}`: the message does not name `{text}`:\n{stderr}"
        );
    }
    for text in &case.lacks {
        assert!(
            !stderr.contains(text),
            "case `{name}`: the message holds the misleading `{text}`:\n{stderr}"
        );
    }
    for text in &case.once {
        assert_eq!(
            stderr.matches(text).count(),
            1,
            "case `{name}`: `{text}` should appear once:\n{stderr}"
        );
    }
    for path in &case.absent {
        assert!(
            !dir.join(path).exists(),
            "case `{name}`: `{path}` was created"
        );
    }
}

/// When a child counts as hung, judged by its own clocks rather than the
/// wall clock alone: a loaded machine slows a child down (it waits to run,
/// gaining no CPU time) without changing what it does, so a verdict on CPU
/// time and on time spent asleep is the same on a busy laptop as on an idle
/// CI box (issue #50, item 13).
#[derive(Clone, Copy, Debug)]
struct HangLimits {
    /// CPU time (user + system, all threads) past which a child that keeps
    /// computing is a hang: a reader of `/dev/zero`, a loop that never ends.
    cpu_s: f64,
    /// Wall time a child may spend asleep without a break (every thread
    /// waiting on something, no CPU time gained): a reader blocked on a
    /// FIFO nothing writes to. Waiting to be scheduled does not count.
    asleep_s: f64,
    /// Wall time past which any child is killed, whatever the load: a
    /// backstop far above any case's run time on a machine ten times
    /// oversubscribed, below a test runner's patience.
    wall_s: f64,
}

/// The limits every case is held to. The costliest case hashes a 6 GB
/// sparse `.npy` (`height_map_npy_6_gb_promising_1x1`): 2 s of CPU time on
/// an idle 2-core machine, 19 s (mostly the kernel's, reading holes) on
/// this one while another job ran; the others take under 6 s.
const CASE_LIMITS: HangLimits = HangLimits {
    cpu_s: 60.0,
    asleep_s: 20.0,
    wall_s: 600.0,
};

/// A child's clocks as `/proc/<pid>` shows them.
#[derive(Clone, Copy, Debug)]
struct ChildClocks {
    /// User and system CPU time of all its threads (and of children it
    /// waited for), seconds.
    cpu_s: f64,
    /// Whether every thread is asleep (`S`): waiting on a pipe, a lock or a
    /// timer rather than running, waiting to run (`R`), stopped (`T`) or in
    /// the disk's hands (`D`).
    asleep: bool,
}

/// Clock ticks per second of `/proc`'s CPU times (`sysconf(_SC_CLK_TCK)`,
/// proc(5)); 100 on Linux where `getconf` does not say.
fn clock_ticks_per_s() -> f64 {
    static TICKS: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *TICKS.get_or_init(|| {
        Command::new("getconf")
            .arg("CLK_TCK")
            .output()
            .ok()
            .and_then(|o| String::from_utf8(o.stdout).ok())
            .and_then(|t| t.trim().parse().ok())
            .unwrap_or(100.0)
    })
}

/// The fields of a `/proc/.../stat` line after the command name (which may
/// hold spaces and parentheses, so the last `)` ends it): the state first.
fn stat_fields(stat: &str) -> Option<Vec<&str>> {
    let close = stat.rfind(')')?;
    Some(stat[close + 1..].split_whitespace().collect())
}

/// The clocks of process `pid`, or None once it is gone.
fn child_clocks(pid: u32) -> Option<ChildClocks> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let fields = stat_fields(&stat)?;
    // utime, stime, cutime, cstime: fields 14 to 17 of proc(5), 11 to 14
    // after the state.
    let ticks: f64 = fields
        .get(11..15)?
        .iter()
        .map(|f| f.parse::<f64>().unwrap_or(0.0))
        .sum();
    let tasks = std::fs::read_dir(format!("/proc/{pid}/task")).ok()?;
    let asleep = tasks.flatten().all(|task| {
        std::fs::read_to_string(task.path().join("stat"))
            .ok()
            .and_then(|s| stat_fields(&s).map(|f| f.first() == Some(&"S")))
            // A thread that ended between the listing and the read.
            .unwrap_or(true)
    });
    Some(ChildClocks {
        cpu_s: ticks / clock_ticks_per_s(),
        asleep,
    })
}

/// Why a child still running counts as hung under `limits`, if it does:
/// `asleep_s` is how long it has been asleep without a break.
fn hang_verdict(
    limits: HangLimits,
    clocks: ChildClocks,
    asleep_s: f64,
    wall_s: f64,
) -> Option<String> {
    if clocks.cpu_s > limits.cpu_s {
        Some(format!(
            "still running after {:.1} s of CPU time (over {} s: a hang)",
            clocks.cpu_s, limits.cpu_s
        ))
    } else if asleep_s > limits.asleep_s {
        Some(format!(
            "asleep for {asleep_s:.1} s without using the CPU (over {} s: blocked, a hang)",
            limits.asleep_s
        ))
    } else if wall_s > limits.wall_s {
        Some(format!(
            "still running after {wall_s:.0} s of wall time (over {} s)",
            limits.wall_s
        ))
    } else {
        None
    }
}

/// The command's output, or a failure naming the case if it hangs under
/// `limits` (it is killed first): a reader that blocks on a pipe or reads
/// `/dev/zero` fails its case instead of hanging the suite, while a case
/// that is merely slow because the machine is busy runs to its end.
fn output_within(mut command: Command, name: &str, limits: HangLimits) -> std::process::Output {
    use std::io::Read;
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = pipe.read_to_end(&mut bytes);
            bytes
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let started = Instant::now();
    let (mut last_cpu_s, mut asleep_since) = (0.0, None::<Instant>);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if let Some(clocks) = child_clocks(child.id()) {
            let now = Instant::now();
            let idle = clocks.asleep && clocks.cpu_s <= last_cpu_s;
            asleep_since = idle.then(|| asleep_since.unwrap_or(now));
            last_cpu_s = clocks.cpu_s;
            let asleep_s = asleep_since.map_or(0.0, |t| (now - t).as_secs_f64());
            let wall_s = (now - started).as_secs_f64();
            if let Some(why) = hang_verdict(limits, clocks, asleep_s, wall_s) {
                let _ = child.kill();
                let _ = child.wait();
                panic!("case `{name}`: {why}; killed");
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    std::process::Output {
        status,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

// ------------------------------------------------------- the hang detector

/// Limits of a second, so the detector's own tests take a few seconds.
const TIGHT: HangLimits = HangLimits {
    cpu_s: 1.0,
    asleep_s: 1.0,
    wall_s: 60.0,
};

/// `sh -c script`.
fn shell(script: &str) -> Command {
    let mut command = Command::new("sh");
    command.args(["-c", script]);
    command
}

/// A child held off the CPU for longer than the CPU and sleep limits (here
/// stopped by a signal for 3 s, as a loaded machine keeps a runnable child
/// waiting) that then does its little work is not a hang. Before, the wall
/// clock alone judged a child, and this one was killed after 1 s.
#[test]
fn hang_detector_waits_for_a_child_held_off_the_cpu() {
    let output = output_within(
        shell("(sleep 3; kill -CONT $$) & kill -STOP $$; echo finished"),
        "held",
        TIGHT,
    );
    assert!(output.status.success(), "{output:?}");
    assert_eq!(String::from_utf8_lossy(&output.stdout), "finished\n");
}

/// A child that has waited 100 s to run (runnable, not asleep) with half a
/// second of CPU time is not a hang under the cases' limits.
#[test]
fn hang_detector_ignores_time_spent_waiting_to_run() {
    let starved = ChildClocks {
        cpu_s: 0.5,
        asleep: false,
    };
    assert_eq!(hang_verdict(CASE_LIMITS, starved, 0.0, 100.0), None);
}

/// A child that sleeps (as a reader blocked on a FIFO does) is a hang once
/// it has slept past the limit.
#[test]
#[should_panic(expected = "case `asleep`: asleep for")]
fn hang_detector_kills_a_child_asleep_too_long() {
    output_within(shell("sleep 30"), "asleep", TIGHT);
}

/// A child that computes without end is a hang once its CPU time passes
/// the limit.
#[test]
#[should_panic(expected = "case `spinning`: still running after")]
fn hang_detector_kills_a_child_that_spins() {
    output_within(shell("while :; do :; done"), "spinning", TIGHT);
}

/// The case's FIFOs, symlinks and sparse files.
fn make_special_files(case: &Case, dir: &Path) {
    let parent = |path: &Path| std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    for name in &case.fifos {
        let path = dir.join(name);
        parent(&path);
        let made = Command::new("mkfifo").arg(&path).status().unwrap();
        assert!(made.success(), "mkfifo {}", path.display());
    }
    for (link, target) in &case.symlinks {
        let path = dir.join(link);
        parent(&path);
        let target = target.replace("<dir>", &dir.display().to_string());
        std::os::unix::fs::symlink(target, path).unwrap();
    }
    for (name, bytes) in &case.sparse {
        let path = dir.join(name);
        parent(&path);
        // Extends what `file` wrote there, so a real header can stand
        // before gigabytes of holes.
        std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(path)
            .unwrap()
            .set_len(*bytes)
            .unwrap();
    }
}

/// A part of a `a: b: c` chain of causes (of some length) that comes twice.
fn repeated_cause(message: &str) -> Option<String> {
    let parts: Vec<&str> = message
        .lines()
        .flat_map(|line| line.split(": "))
        .map(str::trim)
        .filter(|p| p.len() >= 16)
        .collect();
    parts
        .iter()
        .enumerate()
        .find(|(i, p)| parts[i + 1..].contains(p))
        .map(|(_, p)| p.to_string())
}

// ---------------------------------------------------------------- inputs

/// A `.npy` file: the version 1.0 header for `descr` and `shape` (Python
/// syntax), padded as numpy pads it, then `data`.
fn npy(descr: &str, shape: &str, data: &[u8]) -> Vec<u8> {
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

fn f64_bytes(values: impl IntoIterator<Item = f64>) -> Vec<u8> {
    values.into_iter().flat_map(f64::to_le_bytes).collect()
}

/// The real Sensofar file of the reference data (its header is real).
fn reference_plu() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/reference/topography/plu-1.plu"
    ))
    .unwrap()
}

/// An `n` × `n` map of uneven heights up to 10 `scale`.
fn uneven_map(n: u32, scale: f64) -> Vec<u8> {
    npy(
        "<f8",
        &format!("({n}, {n})"),
        &f64_bytes((0..n * n).map(|k| f64::from((k * 37 + k / 7) % 11) * scale)),
    )
}

/// An 8 × 8 map of heights in metres, not flat.
fn small_map() -> Vec<u8> {
    uneven_map(8, 1e-6)
}

/// A gray 64 × 64 PNG (a plain gradient).
fn png() -> Vec<u8> {
    let img = image::GrayImage::from_fn(64, 64, |x, y| image::Luma([((x + y) * 2) as u8]));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    bytes
}

/// A 1000-character YAML value (ten-character words, no spaces).
const LONG: &str = concat!(
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
);

/// 110 characters of [`LONG`]: more than a message may echo of it.
const TOO_LONG: &str = concat!(
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
    "abcdefghij",
);

/// The first lines of a password file: what no message may echo.
const SHADOW: &str =
    "root:$6$SECRETSALT$SECRETHASH:19000:0:99999:7:::\ndaemon:*:19000:0:99999:7:::\n";

/// A height map (`map.npy`, 20 µm pixels) into truncation.
const MAP: &str = "\
name: map
stages:
  surf:
    uses: height-map
    with: { path: map.npy, pixel_m: 20.0e-6 }
  trunc:
    uses: truncation
    inputs: { surface: surf }
    with: { levels: 10 }
";

/// A height map's window (`crop`) into `fem` with the paper's material.
const PATCH: &str = "\
name: patch
stages:
  surf:
    uses: height-map
    with: { path: map.npy, pixel_m: 20.0e-6 }
  epdm:
    uses: material-preset
  patch:
    uses: crop
    inputs: { surface: surf }
    with: { x0: 2, nx: 6 }
  fem:
    uses: fem
    inputs: { surface: patch.height, material: epdm }
    with: { steps: 2, max_area_fraction: 0.1, map_fractions: [0.1], layers: 2 }
";

/// A height map through `surface` (no stitching, kept at its grid).
const SURFACE: &str = "\
name: flat
stages:
  surf:
    uses: height-map
    with: { path: map.npy, pixel_m: 20.0e-6 }
  stats:
    uses: surface
    inputs: { height: surf }
    with: { resolution_m: 0 }
";

/// A tensile CSV (`t.csv`) into a one-term Ogden fit.
const TENSILE: &str = "\
name: tensile
stages:
  tensile:
    uses: tensile-table
    with: { path: t.csv }
  fit:
    uses: material-fit
    inputs: { tensile: tensile }
    with: { model: ogden-1, compare: false, starts: 1 }
";

/// Three UT rows.
const CSV: &str = "mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nUT,1.2,1.9e5\nUT,1.3,2.7e5\n";

/// data/tensile/epdm.csv (UT, PT and BT, 150 rows) with `first` as its
/// first data row.
fn epdm_with_first_row(first: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/tensile/epdm.csv");
    let sample = std::fs::read_to_string(path).unwrap();
    let rows: Vec<&str> = sample
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("mode,"))
        .collect();
    format!(
        "mode,stretch,nominal_stress_pa\n{first}\n{}\n",
        rows.join("\n")
    )
}

/// A DIC stage over the folder `seq/` (frames.csv, force.csv,
/// specimen.json, and the images the case adds).
const DIC: &str = "\
name: dic
stages:
  ut:
    uses: dic
    with: { dir: seq }
";

const CONTACT_IMAGES: &str = "\
name: contact
stages:
  c:
    uses: contact-images
    with: { dir: seq }
";

fn dic_folder(case: Case) -> Case {
    case.file(
        "seq/frames.csv",
        "frame,time_s,file\n0,0.0,frame_000.png\n1,0.5,frame_001.png\n",
    )
    .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n0.5,1.0\n")
    .file(
        "seq/specimen.json",
        r#"{"mode": "UT", "gauge_width_m": 0.01, "thickness_m": 0.0015, "pixel_m": 2.0e-5, "roi_px": [8, 8, 56, 56]}"#,
    )
}

/// `hypercontact export` of the tensile run in `<dir>/out` (cache
/// `<dir>/cache`) as CSV into `out`.
fn export_into(out: &str) -> Case {
    Case::new(&["export", "<dir>/out", "--format", "csv", "--out", out])
        .file("p.yaml", TENSILE)
        .file("t.csv", CSV)
        .before(&[
            "run",
            "<dir>/p.yaml",
            "--out",
            "<dir>/out",
            "--cache",
            "<dir>/cache",
            "-q",
        ])
}

/// A pipeline with a study over `grid` (a YAML map, indented 4).
fn study_over(grid: &str) -> String {
    format!("{TENSILE}study:\n  grid:\n{grid}  collect: [fit.params]\n")
}

// ----------------------------------------------------------------- cases

/// A cache manifest with no outputs, naming `producer` if given (one
/// written before manifests named their build has none).
fn old_manifest(key: &str, producer: Option<&str>) -> String {
    let mut m = serde_json::json!({
        "format": 1, "key": key, "kind": "tensile", "version": 1, "stage": "t",
        "created_unix_s": 0, "compute_s": 0.0, "params": {}, "outputs": {}
    });
    if let Some(p) = producer {
        m["producer"] = p.into();
    }
    m.to_string()
}

macro_rules! cases {
    ($($(#[$attr:meta])* $name:ident: $case:expr;)*) => {
        $( $(#[$attr])* #[test] fn $name() { check(stringify!($name), $case); } )*
    };
}

cases! {
    // --- the pipeline file
    pipeline_file_missing: Case::new(&["run", "<dir>/nowhere.yaml", "-q"]);
    pipeline_is_a_folder: Case::new(&["run", "<dir>/folder", "-q"]).file("folder/x", "");
    yaml_unclosed_flow: Case::run("name: x\nstages: {\n  a: { uses: tensile-table\n", &[])
        .mentions(&["<dir>/p.yaml:4:1"]);
    yaml_bad_indentation: Case::run("name: x\nstages:\n  a:\n    uses: tensile-table\n   with: {}\n", &[])
        .mentions(&["<dir>/p.yaml:5:"]);
    yaml_tab_indentation: Case::run("name: x\nstages:\n\ta:\n\t\tuses: tensile-table\n", &[])
        .mentions(&["<dir>/p.yaml:3:"]);
    yaml_not_a_map: Case::run("- name: x\n- stages: {}\n", &[]);
    yaml_empty_file: Case::run("", &[]);
    // Echoed values are cut to 100 characters (#50, item 12): a long YAML
    // string or stage name is not printed whole.
    yaml_long_value_cut: Case::run(&TENSILE.replace("model: ogden-1", &format!("model: {}", LONG)), &[]).file("t.csv", CSV)
        .mentions(&["`model`", "…"])
        .lacks(TOO_LONG);
    yaml_long_stage_name: Case::run(&TENSILE.replace("  fit:", &format!("  {}:", LONG)), &[]).file("t.csv", CSV)
        .mentions(&["longer than 100 characters", "…"])
        .lacks(TOO_LONG);
    // YAML tags the loader does not honour are refused by name and line.
    yaml_binary_tag: Case::run(&TENSILE.replace("path: t.csv", "path: !!binary dC5jc3Y="), &[]).file("t.csv", CSV)
        .mentions(&["<dir>/p.yaml:5:", "`!!binary`", "not honoured"]);
    yaml_timestamp_tag: Case::run(&TENSILE.replace("starts: 1", "starts: !!timestamp 2001-12-14"), &[]).file("t.csv", CSV)
        .mentions(&["<dir>/p.yaml:9:", "`!!timestamp`", "not honoured"]);
    missing_name: Case::run(&TENSILE.replace("name: tensile\n", ""), &[]);
    missing_stages: Case::run("name: x\n", &[]);
    unknown_top_level_key: Case::run(&format!("{TENSILE}stagse: {{}}\n"), &[]);
    unknown_stage_key: Case::run(&TENSILE.replace("    with: { path: t.csv }", "    wiht: { path: t.csv }"), &[]);
    missing_uses: Case::run("name: x\nstages:\n  tensile:\n    with: { path: t.csv }\n", &[]);
    unknown_stage_kind: Case::run(&TENSILE.replace("uses: material-fit", "uses: material-fitt"), &[]);
    bad_stage_name_slash: Case::run(&TENSILE.replace("  fit:", "  fit/ogden:"), &[]).file("t.csv", CSV);
    bad_stage_name_dotdot: Case::run(&TENSILE.replace("  fit:", "  ..:"), &[]).file("t.csv", CSV);
    pipeline_name_escapes: Case::new(&["run", "<dir>/p.yaml", "-q"])
        .file("p.yaml", TENSILE.replace("name: tensile", "name: ../../escaped"))
        .file("t.csv", CSV)
        .cwd("work")
        .absent("escaped");
    duplicate_stage_name: Case::run(&format!("{TENSILE}  tensile:\n    uses: tensile-table\n    with: {{ path: other.csv }}\n"), &[]).file("t.csv", CSV)
        .mentions(&["<dir>/p.yaml:10:3"]);
    duplicate_input_key: Case::run(&TENSILE.replace("inputs: { tensile: tensile }", "inputs: { tensile: tensile, tensile: tensile }"), &[]).file("t.csv", CSV)
        .mentions(&["<dir>/p.yaml:8:"]);
    duplicate_input_label: Case::run(&TENSILE.replace("inputs: { tensile: tensile }", "inputs:\n      tensile:\n        UT: tensile\n        UT: tensile"), &[]).file("t.csv", CSV)
        .mentions(&["<dir>/p.yaml:11:"]);
    empty_stages: Case::run("name: x\nstages: {}\n", &[]);
    // --- the Slurm executor's inputs (issue #19)
    detach_without_slurm: Case::run(TENSILE, &["--detach"]).file("t.csv", CSV)
        .mentions(&["--executor slurm"]);
    executor_unknown: Case::run(TENSILE, &["--executor", "pbs"]).file("t.csv", CSV).exit(2);
    slurm_profile_missing: Case::run(TENSILE, &["--executor", "slurm", "--slurm-profile", "<dir>/site.yaml"])
        .file("t.csv", CSV)
        .mentions(&["<dir>/site.yaml", "Slurm site profile"]);
    slurm_profile_unknown_key: Case::run(TENSILE, &["--executor", "slurm", "--slurm-profile", "<dir>/site.yaml"])
        .file("t.csv", CSV)
        .file("site.yaml", "partition: compute\nlimit: { cpus: 2 }\n")
        .mentions(&["<dir>/site.yaml:2:1"]);
    slurm_profile_bad_time: Case::run(TENSILE, &["--executor", "slurm", "--slurm-profile", "<dir>/site.yaml"])
        .file("t.csv", CSV)
        .file("site.yaml", "limits:\n  time: 90 minutes\n")
        .mentions(&["<dir>/site.yaml:2:", "time limit"]);
    slurm_pipeline_bad_mem: Case::run(&TENSILE.replace("    uses: material-fit\n", "    uses: material-fit\n    slurm: { mem: 16 GB }\n"), &[])
        .file("t.csv", CSV)
        .mentions(&["<dir>/p.yaml:", "stage `fit`", "amount of memory"]);
    status_without_submission: Case::new(&["status", "<dir>/p.yaml", "--out", "<dir>/out"])
        .file("p.yaml", TENSILE)
        .mentions(&["<dir>/out/slurm", "--executor slurm"]);
    exec_stage_job_missing: Case::new(&["exec-stage", "<dir>/job.json"])
        .mentions(&["<dir>/job.json"]);
    exec_stage_job_garbage: Case::new(&["exec-stage", "<dir>/job.json"])
        .file("job.json", "{ \"format\": 1, \"pipeline\": ")
        .mentions(&["<dir>/job.json"]);
    exec_stage_job_format: Case::new(&["exec-stage", "<dir>/job.json"])
        .file("job.json", "{\"format\": 9, \"pipeline\": \"p.yaml\", \"sets\": [], \"values\": [], \"cache\": \"c\", \"job\": {\"stage\": \"a\", \"key\": \"k\"}}")
        .mentions(&["<dir>/job.json", "format 9"]);
    // A key cut at byte 12 split the seventh `é` and panicked.
    exec_stage_job_multibyte_key: Case::new(&["exec-stage", "<dir>/job.json"])
        .file("p.yaml", TENSILE).file("t.csv", CSV)
        .file("job.json", "{\"format\": 1, \"pipeline\": \"p.yaml\", \"sets\": [], \"values\": [], \"cache\": \"c\", \"job\": {\"stage\": \"fit\", \"key\": \"aééééééééééééé\"}}")
        .mentions(&["`fit`", "aééééééééééé", "submit again"]);
    cycle: Case::run("name: c\nstages:\n  a:\n    uses: truncation\n    inputs: { surface: b }\n  b:\n    uses: surface\n    inputs: { height: a.profile }\n", &[]);
    input_names_missing_stage: Case::run(&TENSILE.replace("{ tensile: tensile }", "{ tensile: tensil }"), &[]).file("t.csv", CSV);
    input_names_missing_output: Case::run(&TENSILE.replace("{ tensile: tensile }", "{ tensile: tensile.table }"), &[]).file("t.csv", CSV);
    unknown_input: Case::run(&TENSILE.replace("{ tensile: tensile }", "{ tensile: tensile, extra: tensile }"), &[]).file("t.csv", CSV);
    missing_input: Case::run(&TENSILE.replace("    inputs: { tensile: tensile }\n", ""), &[]).file("t.csv", CSV);
    type_mismatch_table_for_field: Case::run(&format!("{TENSILE}  trunc:\n    uses: truncation\n    inputs: {{ surface: tensile }}\n"), &[]).file("t.csv", CSV);
    type_mismatch_missing_columns: Case::run(&format!("{TENSILE}  contact:\n    uses: icm\n    inputs: {{ profile: tensile, material: fit.material }}\n"), &[]).file("t.csv", CSV);

    // --- parameters
    param_wrong_type: Case::run(&TENSILE.replace("starts: 1", "starts: many"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`"]);
    param_out_of_range: Case::run(&TENSILE.replace("starts: 1", "starts: 0"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`"]);
    param_nan: Case::run(&MAP.replace("pixel_m: 20.0e-6", "pixel_m: .nan"), &[]).file("map.npy", small_map())
        .mentions(&["`surf`", "`pixel_m`"]);
    param_infinite: Case::run(&MAP.replace("pixel_m: 20.0e-6", "pixel_m: .inf"), &[]).file("map.npy", small_map())
        .mentions(&["`surf`", "`pixel_m`"]);
    param_zero_for_positive: Case::run(&MAP.replace("pixel_m: 20.0e-6", "pixel_m: 0"), &[]).file("map.npy", small_map())
        .mentions(&["`surf`", "`pixel_m`"]);
    param_negative_for_positive: Case::run(&MAP.replace("pixel_m: 20.0e-6", "pixel_m: -2.0e-5"), &[]).file("map.npy", small_map())
        .mentions(&["`surf`", "`pixel_m`"]);
    param_unknown_choice: Case::run(&TENSILE.replace("model: ogden-1", "model: ogden-7"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`model`"]);
    param_unknown: Case::run(&TENSILE.replace("starts: 1", "start: 1"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`start`"]);
    param_nested_out_of_range: Case::run(&TENSILE.replace("starts: 1", "weights: { UT: -1 }"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`weights.UT`"]);
    param_list_out_of_range: Case::run(&MAP.replace("levels: 10", "patch_fractions: [0.5, 1.5]"), &[]).file("map.npy", small_map())
        .mentions(&["`trunc`", "`patch_fractions.1`"]);
    param_poisson_out_of_range: Case::run(&format!("{TENSILE}  contact:\n    uses: icm\n    inputs: {{ profile: tensile, material: fit.material }}\n    with: {{ poisson: 0.7 }}\n"), &[]).file("t.csv", CSV)
        .mentions(&["`contact`", "`poisson`"]);
    param_missing_required: Case::run(&MAP.replace("path: map.npy, ", ""), &[])
        .mentions(&["`surf`", "`path`"]);
    param_missing_file: Case::run(TENSILE, &[])
        .mentions(&["`tensile`", "`path`"]);
    // A folder given for a file is refused at planning, before it is
    // hashed (#50, item 12): before, the folder was hashed whole, and a
    // pipe inside it failed the hash instead.
    param_file_is_a_folder: Case::run(TENSILE, &[]).file("t.csv/x", "")
        .mentions(&["<dir>/t.csv", "`tensile`", "`path`", "is a folder"]);
    param_file_is_a_folder_holding_a_pipe: Case::run(TENSILE, &[]).fifo("t.csv/pipe")
        .mentions(&["<dir>/t.csv", "`tensile`", "`path` takes a file"])
        .lacks("pipe");
    with_file_missing: Case::run(&TENSILE.replace("with: { path: t.csv }", "with_file: recipe.yaml"), &[]);

    // --- `--set`
    set_without_equals: Case::run(TENSILE, &["--set", "fit.starts"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_without_param: Case::run(TENSILE, &["--set", "fit=3"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_empty_stage: Case::run(TENSILE, &["--set", ".starts=3"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_empty_param: Case::run(TENSILE, &["--set", "fit.=3"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_empty_path: Case::run(TENSILE, &["--set", "=3"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_unknown_stage: Case::run(TENSILE, &["--set", "fitt.starts=3"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_unknown_param: Case::run(TENSILE, &["--set", "fit.startz=3"]).file("t.csv", CSV)
        .mentions(&["`fit`", "`startz`"]);
    set_wrong_type: Case::run(TENSILE, &["--set", "fit.starts=three"]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`"]);
    set_out_of_range: Case::run(TENSILE, &["--set", "fit.starts=0"]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`"]);
    set_value_not_yaml: Case::run(TENSILE, &["--set", "fit.starts=[1"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    set_multibyte_unknown_choice: Case::run(TENSILE, &["--set", "fit.model=ögden-1"]).file("t.csv", CSV)
        .mentions(&["`fit`", "`model`"]);
    set_multibyte_wrong_type: Case::run(TENSILE, &["--set", "fit.starts=🦀🦀🦀"]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`"]);
    set_multibyte_missing_file: Case::run(TENSILE, &["--set", "tensile.path=données-été.csv"]).file("t.csv", CSV)
        .mentions(&["`tensile`", "`path`", "--set"]);
    set_multibyte_stage_name: Case::run(TENSILE, &["--set", "fït.starts=2"]).file("t.csv", CSV)
        .mentions(&["--set"]);
    // 38 letters, then `€` (3 bytes) across byte 40 of the changed value,
    // with or without the quote the dry run shows it in. Must not panic.
    set_multibyte_at_byte_40_dry_run: Case::run(
        "name: r\nstages:\n  report:\n    uses: report\n    with: { title: plain }\n",
        &["--dry-run", "--set", &format!("report.title={}€€€ and more after it", "a".repeat(38))],
    )
    .before(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "--cache", "<dir>/cache", "-q"])
    .exit(0);
    // Dry-run columns stay aligned past a multi-byte stage name.
    dry_run_multibyte_stage_name: Case::run(
        &MAP.replace("  surf:", "  höhe:").replace("{ surface: surf }", "{ surface: höhe }"),
        &["--dry-run"],
    )
        .file("map.npy", small_map())
        .exit(0);
    force_unknown_stage: Case::run(TENSILE, &["--force", "fitt"]).file("t.csv", CSV);
    only_unknown_stage: Case::run(TENSILE, &["--only", "fitt"]).file("t.csv", CSV);

    // --- studies
    study_grid_empty_values: Case::study(&study_over("    fit.starts: []\n"), &[]).file("t.csv", CSV)
        .mentions(&["`fit.starts`"]);
    study_grid_unknown_param: Case::study(&study_over("    fit.startz: [1, 2]\n"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`startz`"]);
    study_grid_unknown_stage: Case::study(&study_over("    fitt.starts: [1, 2]\n"), &[]).file("t.csv", CSV);
    study_grid_value_out_of_range: Case::study(&study_over("    fit.starts: [1, 0]\n"), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`"]);
    study_grid_not_a_list: Case::study(&study_over("    fit.starts: 3\n"), &[]).file("t.csv", CSV)
        .mentions(&["fit.starts"]);
    study_missing: Case::study(TENSILE, &[]).file("t.csv", CSV);

    // --- the cache commands (clap refuses the days before the program runs)
    cache_gc_days_nan: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--older-than-days", "NaN"]).exit(2);
    cache_gc_days_inf: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--older-than-days", "inf"]).exit(2);
    cache_gc_days_negative: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--older-than-days=-1"]).exit(2);
    cache_gc_days_huge: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--older-than-days", "1e300"]).exit(2);
    cache_gc_days_text: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--older-than-days", "ten"]).exit(2);
    cache_gc_days_negative_apart: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--older-than-days", "-3"])
        .exit(2)
        .mentions(&["-3 days", "from 0 to 36525"])
        .lacks("unexpected argument");
    // `cache clean` removes a cache only: a folder of other files is named
    // and kept (#31, 1); a cache a run made is removed whole.
    cache_clean_not_a_cache: Case::new(&["cache", "clean", "--cache", "<dir>/x"])
        .file("x/ch/a.tex", "notes")
        .mentions(&["not a hypercontact cache", "ch/"]);
    cache_clean_removes_a_cache: Case::new(&["cache", "clean", "--cache", "<dir>/cache"])
        .file("p.yaml", TENSILE)
        .file("t.csv", CSV)
        .before(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "--cache", "<dir>/cache", "-q"])
        .absent("cache")
        .exit(0);
    run_cache_in_a_folder_of_other_files: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "--cache", "<dir>/x", "-q"])
        .file("p.yaml", TENSILE)
        .file("t.csv", CSV)
        .file("x/thesis.tex", "chapter 1")
        .mentions(&["not a hypercontact cache", "thesis.tex"]);
    // Outputs inside the cache, or the cache inside the outputs, are refused
    // before anything is written (#31, 2).
    run_out_inside_the_cache: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/cache/entries", "--cache", "<dir>/cache", "-q"])
        .file("p.yaml", TENSILE)
        .file("t.csv", CSV)
        .mentions(&["overlap", "inside the cache"]);
    run_cache_inside_the_out: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "--cache", "<dir>/out/../out/c", "-q"])
        .file("p.yaml", TENSILE)
        .file("t.csv", CSV)
        .absent("out")
        .mentions(&["overlap", "inside the outputs"]);
    // `export --out` inside a cache (or at its root), the run folder itself
    // or a stage's folder is refused before anything is written (#50, 5);
    // a folder of its own inside the run folder is fine.
    export_out_inside_the_cache: export_into("<dir>/cache/entries/x")
        .absent("cache/entries/x")
        .mentions(&["--out <dir>/cache/entries/x lies inside the cache <dir>/cache"]);
    export_out_at_the_cache_root: export_into("<dir>/cache")
        .absent("cache/fit")
        .mentions(&["--out <dir>/cache is the root of the cache <dir>/cache"]);
    export_out_inside_the_cache_through_a_link: export_into("<dir>/link/entries/x")
        .symlink("link", "<dir>/cache")
        .absent("cache/entries/x")
        .mentions(&["--out <dir>/link/entries/x lies inside the cache <dir>/link"]);
    export_out_the_run_folder: export_into("<dir>/out/.")
        .mentions(&["the run folder <dir>/out itself"]);
    export_out_in_a_stage_folder: export_into("<dir>/out/fit/csv")
        .absent("out/fit/csv")
        .mentions(&["inside <dir>/out/fit, which the run wrote"]);
    export_out_a_folder_of_its_own_in_the_run: export_into("<dir>/out/tables").exit(0);
    // Listing a cache that is not there says so and creates nothing.
    cache_ls_missing_dir: Case::new(&["cache", "ls", "--cache", "<dir>/missing/dir"])
        .exit(0)
        .absent("missing");
    cache_gc_missing_dir: Case::new(&["cache", "gc", "--cache", "<dir>/missing/dir"])
        .exit(0)
        .absent("missing");

    // --- tensile CSV
    csv_empty: Case::run(TENSILE, &[]).file("t.csv", "")
        .mentions(&["<dir>/t.csv", "`tensile`"])
        .lacks("(the table has: )");
    csv_header_only: Case::run(TENSILE, &[]).file("t.csv", "mode,stretch,nominal_stress_pa\n")
        .mentions(&["<dir>/t.csv", "`tensile`"])
        .lacks("holds str values");
    csv_text_in_number: Case::run(TENSILE, &[]).file("t.csv", "mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nUT,1.2,abc\nUT,1.3,2.7e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`", "line 3", "nominal_stress_pa"]);
    // The bad cell is on line 6 of the file, after three comment lines.
    csv_text_in_number_after_comments: Case::run(TENSILE, &[]).file("t.csv", "# a comment\n# another\nmode,stretch,nominal_stress_pa\n# units: 1, Pa\nUT,1.1,1.0e5\nUT,1.2x,1.9e5\nUT,1.3,2.7e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`", "line 6", "stretch"]);
    csv_wrong_columns: Case::run(TENSILE, &[]).file("t.csv", "mode,lambda,stress\nUT,1.1,1.0e5\nUT,1.2,1.9e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`"]);
    csv_ragged_row: Case::run(TENSILE, &[]).file("t.csv", "mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nUT,1.2\nUT,1.3,2.7e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`"]);
    csv_unknown_mode: Case::run(TENSILE, &[]).file("t.csv", "mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nXT,1.2,1.9e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`"]);
    csv_stretch_not_increasing: Case::run(TENSILE, &[]).file("t.csv", "mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nUT,1.3,2.7e5\nUT,1.2,1.9e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`"]);
    csv_negative_stress_in_tension: Case::run(TENSILE, &[]).file("t.csv", "mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nUT,1.2,-1.9e5\nUT,1.3,2.7e5\n")
        .mentions(&["<dir>/t.csv", "`tensile`"]);
    csv_not_utf8: Case::run(TENSILE, &[]).file("t.csv", b"mode,stretch,nominal_stress_pa\nUT,1.1,1.0e5\nUT,1.2,\xff\xfe\n")
        .mentions(&["<dir>/t.csv", "`tensile`"]);

    // --- material-fit
    // The paper's data with `UT,1.0,0` in front: `Singular value was NaN`
    // in the Ogden-6 fit, alone or within the comparison. The reference
    // state is valid data: the fit now runs.
    fit_first_ut_row_zero_stress: Case::run(&TENSILE.replace("{ model: ogden-1, compare: false, starts: 1 }", "{ model: ogden-6, compare: true }"), &[]).file("t.csv", epdm_with_first_row("UT,1.0,0"))
        .exit(0);
    fit_first_ut_row_zero_stress_compare: Case::run(&TENSILE.replace("{ model: ogden-1, compare: false, starts: 1 }", "{ model: neo-hookean, compare: true }"), &[]).file("t.csv", epdm_with_first_row("UT,1.0,0"))
        .exit(0);
    fit_too_few_points: Case::run(&TENSILE.replace("model: ogden-1", "model: ogden-6"), &[]).file("t.csv", CSV);

    // --- .npy height maps
    // --- the finite-strain patch (issue #33)
    crop_window_leaves_the_map: Case::run(&PATCH.replace("x0: 2, nx: 6", "x0: 4, nx: 6"), &[]).file("map.npy", small_map())
        .mentions(&["nx = 6 from x0 = 4 reaches point 10"]);
    crop_coarsened_to_one_point: Case::run(&PATCH.replace("x0: 2, nx: 6", "x0: 2, nx: 6, coarsen: 4"), &[]).file("map.npy", small_map())
        .mentions(&["fewer than 2 along x"]);
    fem_missing_point_in_window: Case::run(PATCH, &[]).file("map.npy", {
        let mut bytes = small_map();
        // Point (3, 1) of the 8 × 8 map NaN: (1, 1) of the crop fem is given.
        let at = bytes.len() - 8 * 64 + 8 * (3 * 8 + 1);
        bytes[at..at + 8].copy_from_slice(&f64::NAN.to_le_bytes());
        bytes
    })
        .mentions(&["missing (NaN)", "patch point (1, 1)"]);
    fem_map_fraction_beyond_curve: Case::run(&PATCH.replace("map_fractions: [0.1]", "map_fractions: [0.2]"), &[]).file("map.npy", small_map())
        .mentions(&["map_fractions.0"]);
    npy_garbage: Case::run(MAP, &[]).file("map.npy", "this is not a numpy file at all\n")
        .mentions(&["<dir>/map.npy", "`surf`"]);
    npy_truncated: Case::run(MAP, &[]).file("map.npy", &small_map()[..300])
        .mentions(&["<dir>/map.npy", "`surf`"]);
    npy_huge_shape: Case::run(MAP, &[]).file("map.npy", npy("<f8", "(1000000, 1000000)", &f64_bytes([1e-6; 64])))
        .mentions(&["<dir>/map.npy", "`surf`"]);
    npy_wrong_dtype: Case::run(MAP, &[]).file("map.npy", npy("<i8", "(8, 8)", &[0u8; 512]))
        .mentions(&["<dir>/map.npy", "`surf`"]);
    npy_3d: Case::run(MAP, &[]).file("map.npy", npy("<f8", "(2, 4, 8)", &f64_bytes([1e-6; 64])))
        .mentions(&["<dir>/map.npy", "`surf`"]);
    npy_1d: Case::run(MAP, &[]).file("map.npy", npy("<f8", "(64,)", &f64_bytes([1e-6; 64])))
        .mentions(&["<dir>/map.npy", "`surf`"]);
    npy_missing_file: Case::run(MAP, &[])
        .mentions(&["`surf`", "`path`"]);
    // Heights near 1e301 m overflow the PSD; the message must not send the
    // user to the Hurst range.
    surface_overflowing_heights: Case::run(SURFACE, &[])
        .file("map.npy", uneven_map(32, 1e300))
        .mentions(&["`stats`"])
        .lacks("hurst_lambda");
    surface_flat_map: Case::run(SURFACE, &[]).file("map.npy", npy("<f8", "(32, 32)", &f64_bytes([1e-6; 1024])))
        .mentions(&["`stats`"]);

    // --- files whose contents a message must not echo (#50, item 11): a
    // credentials file given as an input is named by its kind and its
    // first 8 bytes in hex, never by its text.
    height_map_credentials_file: Case::run(&MAP.replace("path: map.npy", "path: shadow"), &[]).file("shadow", SHADOW)
        .lacks("SECRET").lacks("root:")
        .mentions(&["<dir>/shadow", "text (first bytes 72 6f 6f 74 3a 24 36 24)"]);
    height_map_credentials_file_named_npy: Case::run(MAP, &[]).file("map.npy", SHADOW)
        .lacks("SECRET").lacks("root:")
        .mentions(&["<dir>/map.npy", "not a NumPy .npy file"]);
    tensile_csv_credentials_file: Case::run(TENSILE, &[]).file("t.csv", SHADOW)
        .lacks("SECRET").lacks("root:")
        .mentions(&["<dir>/t.csv", "line 1", "not a CSV header of column names"]);
    tensile_csv_semicolon_credentials: Case::run(TENSILE, &[]).file("t.csv", "user;password=SECRET\nroot;x\n")
        .lacks("SECRET")
        .mentions(&["<dir>/t.csv", "line 1", "separated by semicolons"]);
    dic_frames_credentials_file: dic_folder(Case::run(DIC, &[])).file("seq/frames.csv", SHADOW)
        .lacks("SECRET").lacks("root:")
        .mentions(&["<dir>/seq/frames.csv", "not a CSV header of column names"]);
    // --- images of a DIC folder
    dic_garbage_png: dic_folder(Case::run(DIC, &[]))
        .file("seq/frame_000.png", "not a png\n")
        .file("seq/frame_001.png", "not a png\n");
    dic_truncated_png: dic_folder(Case::run(DIC, &[]))
        .file("seq/frame_000.png", &png()[..60])
        .file("seq/frame_001.png", png());
    dic_missing_image: dic_folder(Case::run(DIC, &[])).file("seq/frame_000.png", png());
    // No frames.csv and no times in the names: the error says what a name
    // must carry.
    dic_frames_without_times: Case::run(DIC, &[])
        .file("seq/frame_000.png", png())
        .file("seq/frame_001.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n0.5,1.0\n")
        .mentions(&["<dir>/seq/frame_000.png", "frames.csv", "img_000_t0.000s.tif"]);
    contact_images_two_frames_of_one_time: Case::run(CONTACT_IMAGES, &[])
        .file("seq/img_1_t1s.png", png())
        .file("seq/img_2_t1000ms.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n0.5,1.0\n")
        .mentions(&["<dir>/seq/img_2_t1000ms.png", "img_1_t1s.png", "`c`"]);
    dic_text_in_frames_csv: Case::run(DIC, &[])
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,frame_000.png\n1,half,frame_001.png\n")
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n0.5,1.0\n");

    // --- where the products go
    out_dir_not_writable: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/locked/out", "--cache", "<dir>/cache", "-q"])
        .file("p.yaml", TENSILE)
        .file("t.csv", CSV)
        .read_only("locked")
        .once("Permission denied");
    out_dir_is_a_file: Case::run(TENSILE, &[]).file("t.csv", CSV).file("out", "a file, not a folder\n")
        .mentions(&["<dir>/out"]);

    // #31 stages
    // A quoted number is text in YAML (#31, 11): refused, saying how to
    // write it; `--set` reads its value as YAML, so 12 stays a number.
    param_quoted_number: Case::run(&MAP.replace("levels: 10", "levels: \"10\""), &[]).file("map.npy", small_map())
        .mentions(&["`trunc`", "`levels`", "write 10, not \"10\""]);
    param_quoted_number_for_an_integer: Case::run(&TENSILE.replace("starts: 1", "starts: \"3\""), &[]).file("t.csv", CSV)
        .mentions(&["`fit`", "`starts`", "write 3, not \"3\""]);
    set_levels_number_is_a_number: Case::run(MAP, &["--set", "trunc.levels=12"]).file("map.npy", small_map())
        .exit(0);
    set_levels_quoted_is_text: Case::run(MAP, &["--set", "trunc.levels=\"12\""]).file("map.npy", small_map())
        .mentions(&["--set", "`levels`", "write 12, not \"12\""]);
    // frames.csv listing a frame twice, or one file at two times (#31, 9).
    contact_images_frame_listed_twice: Case::run(CONTACT_IMAGES, &[])
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n0,1.0,b.png\n")
        .file("seq/a.png", png())
        .file("seq/b.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["<dir>/seq/frames.csv", "`c`", "frame 0 is listed twice", "line 2", "line 3"]);
    contact_images_file_at_two_times: Case::run(CONTACT_IMAGES, &[])
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n1,1.0,a.png\n")
        .file("seq/a.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["<dir>/seq/frames.csv", "`c`", "a.png is listed for two frames", "line 2", "line 3"]);
    // A reference frame in contact gave A/A0 = 0 in every frame (#31, 9).
    contact_images_reference_in_contact: Case::run(&CONTACT_IMAGES.replace("{ dir: seq }", "{ dir: seq, reference_frame: 1, clock_offset_s: 0 }"), &[])
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n1,1.0,b.png\n")
        .file("seq/a.png", png())
        .file("seq/b.png", {
            let img = image::GrayImage::from_pixel(64, 64, image::Luma([20u8]));
            let mut bytes = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).unwrap();
            bytes
        })
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["`c`", "`reference_frame` = 1", "b.png", "in contact"]);
    // An offset far beyond the log named no parameter (#31, 15).
    contact_images_clock_offset_beyond_the_log: Case::run(&CONTACT_IMAGES.replace("{ dir: seq }", "{ dir: seq, clock_offset_s: 1e9 }"), &[])
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n1,1.0,b.png\n")
        .file("seq/a.png", png())
        .file("seq/b.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["`c`", "`clock_offset_s` = 1000000000 s", "upper bound 1 s", "between 0 and 1 s"])
        .lacks("was taken at");
    // contact-compare on inputs that do not belong together (#31, 8): a
    // 4 × 4 px scan of 20 µm against a 64 px camera view of 6.5 µm (416 µm)
    // gave a result; a view_maps key that is no response was ignored.
    compare_view_larger_than_the_scan: Case::run("name: cmp\nstages:\n  surf:\n    uses: height-map\n    with: { path: map.npy, pixel_m: 20.0e-6 }\n  c:\n    uses: contact-images\n    with: { dir: seq, clock_offset_s: 0 }\n  cmp:\n    uses: contact-compare\n    inputs: { contact: c.contact, observed_maps: c.contact_maps, surface: surf }\n    with: { view_maps: {} }\n", &[])
        .file("map.npy", npy("<f8", "(4, 4)", &f64_bytes((0..16).map(|k| f64::from(k % 5) * 1e-6))))
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n1,1.0,b.png\n")
        .file("seq/a.png", png())
        .file("seq/b.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["`cmp`", "416 × 416 µm", "80 × 80 µm", "larger than the scan"]);
    compare_view_maps_key_not_a_response: Case::run("name: cmp\nstages:\n  surf:\n    uses: height-map\n    with: { path: map.npy, pixel_m: 20.0e-6 }\n  c:\n    uses: contact-images\n    with: { dir: seq, clock_offset_s: 0 }\n  cmp:\n    uses: contact-compare\n    inputs: { contact: c.contact, observed_maps: c.contact_maps, surface: surf }\n    with: { view_maps: { ghost: truncation } }\n", &[])
        .file("map.npy", uneven_map(128, 1e-6))
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n1,1.0,b.png\n")
        .file("seq/a.png", png())
        .file("seq/b.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["`cmp`", "`view_maps`", "`ghost`", "none connected"]);
    // #49: a same_physics name that is not a wired response.
    compare_same_physics_not_a_response: Case::run("name: cmp\nstages:\n  surf:\n    uses: height-map\n    with: { path: map.npy, pixel_m: 20.0e-6 }\n  c:\n    uses: contact-images\n    with: { dir: seq, clock_offset_s: 0 }\n  cmp:\n    uses: contact-compare\n    inputs: { contact: c.contact, observed_maps: c.contact_maps, surface: surf }\n    with: { same_physics: [bem] }\n", &[])
        .file("map.npy", uneven_map(128, 1e-6))
        .file("seq/frames.csv", "frame,time_s,file\n0,0.0,a.png\n1,1.0,b.png\n")
        .file("seq/a.png", png())
        .file("seq/b.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n1.0,1.0\n2.0,2.0\n")
        .mentions(&["`cmp`", "`same_physics`", "`bem`", "none connected"]);

    // #31 cliread
    // Every file the command line names is refused unopened unless it is a
    // regular file (item 5): before, each FIFO hung for ever and each
    // `/dev/zero` read until memory ran out (4.1 GB+).
    run_pipeline_fifo: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "-q"]).fifo("p.yaml")
        .mentions(&["<dir>/p.yaml", "not a regular file (a pipe)"]);
    run_pipeline_dev_zero: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "-q"]).symlink("p.yaml", "/dev/zero")
        .mentions(&["<dir>/p.yaml", "character device"]);
    // A pipeline is hand-written YAML: 20 MiB is refused by its size, unread.
    run_pipeline_too_large: Case::new(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "-q"]).sparse("p.yaml", 20 << 20)
        .mentions(&["<dir>/p.yaml", "20 MiB", "pipeline files are at most 16 MiB"]);
    exec_stage_job_fifo: Case::new(&["exec-stage", "<dir>/job.json"]).fifo("job.json")
        .mentions(&["<dir>/job.json", "not a regular file (a pipe)"]);
    exec_stage_job_dev_zero: Case::new(&["exec-stage", "<dir>/job.json"]).symlink("job.json", "/dev/zero")
        .mentions(&["<dir>/job.json", "character device"]);
    status_pipeline_fifo: Case::new(&["status", "<dir>/p.yaml", "--out", "<dir>/out"]).fifo("p.yaml")
        .mentions(&["<dir>/p.yaml", "not a regular file (a pipe)"]);
    status_pipeline_dev_zero: Case::new(&["status", "<dir>/p.yaml", "--out", "<dir>/out"]).symlink("p.yaml", "/dev/zero")
        .mentions(&["<dir>/p.yaml", "character device"]);
    status_submission_fifo: Case::new(&["status", "<dir>/p.yaml", "--out", "<dir>/out"]).file("p.yaml", TENSILE).fifo("out/slurm/submission.json")
        .mentions(&["<dir>/out/slurm/submission.json", "not a regular file (a pipe)"]);
    status_submission_dev_zero: Case::new(&["status", "<dir>/p.yaml", "--out", "<dir>/out"]).file("p.yaml", TENSILE).symlink("out/slurm/submission.json", "/dev/zero")
        .mentions(&["<dir>/out/slurm/submission.json", "character device"]);
    slurm_profile_fifo: Case::run(TENSILE, &["--executor", "slurm", "--slurm-profile", "<dir>/site.yaml"]).file("t.csv", CSV).fifo("site.yaml")
        .mentions(&["<dir>/site.yaml", "Slurm site profile", "not a regular file (a pipe)"]);
    slurm_profile_dev_zero: Case::run(TENSILE, &["--executor", "slurm", "--slurm-profile", "<dir>/site.yaml"]).file("t.csv", CSV).symlink("site.yaml", "/dev/zero")
        .mentions(&["<dir>/site.yaml", "Slurm site profile", "character device"]);
    cache_gc_keep_fifo: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--keep", "<dir>/k.yaml"])
        .file("p.yaml", TENSILE).file("t.csv", CSV)
        .before(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "--cache", "<dir>/cache", "-q"])
        .fifo("k.yaml")
        .mentions(&["<dir>/k.yaml", "not a regular file (a pipe)"]);
    cache_gc_keep_dev_zero: Case::new(&["cache", "gc", "--cache", "<dir>/cache", "--keep", "<dir>/k.yaml"])
        .file("p.yaml", TENSILE).file("t.csv", CSV)
        .before(&["run", "<dir>/p.yaml", "--out", "<dir>/out", "--cache", "<dir>/cache", "-q"])
        .symlink("k.yaml", "/dev/zero")
        .mentions(&["<dir>/k.yaml", "character device"]);
    // The previous run's record: a run that cannot read it fails before
    // any stage (before, the FIFO hung and `/dev/zero` was swallowed, exit 0).
    provenance_fifo: Case::run(TENSILE, &[]).file("t.csv", CSV).fifo("out/provenance.json")
        .mentions(&["<dir>/out/provenance.json", "not a regular file (a pipe)", "--out"]);
    provenance_dev_zero: Case::run(TENSILE, &[]).file("t.csv", CSV).symlink("out/provenance.json", "/dev/zero")
        .mentions(&["<dir>/out/provenance.json", "character device", "--out"]);
    // A with_file recipe (item 6): 3 GiB of holes is refused by its size
    // (before: 6.2 GB RSS), a pipe unopened.
    with_file_sparse_3_gib: Case::run(&TENSILE.replace("with: { path: t.csv }", "with_file: recipe.yaml"), &[]).sparse("recipe.yaml", 3 << 30)
        .mentions(&["<dir>/recipe.yaml", "3.0 GiB", "with_file recipes are at most 16 MiB"]);
    with_file_fifo: Case::run(&TENSILE.replace("with: { path: t.csv }", "with_file: recipe.yaml"), &[]).fifo("recipe.yaml")
        .mentions(&["<dir>/recipe.yaml", "not a regular file (a pipe)"]);
    // A profile written as a list (item 10): before, read by position and
    // its first item reported as key `0`.
    slurm_profile_a_list: Case::run(TENSILE, &["--executor", "slurm", "--slurm-profile", "<dir>/site.yaml"]).file("t.csv", CSV)
        .file("site.yaml", "- partition: compute\n- limits: { cpus: 2 }\n")
        .mentions(&["<dir>/site.yaml", "must be a map of settings", "found a list"])
        .lacks("`0`");
    // An entry of a data folder that is no file is named, not the folder
    // (item 14).
    dic_folder_fifo_entry: dic_folder(Case::run(DIC, &[])).file("seq/frame_000.png", png()).file("seq/frame_001.png", png())
        .fifo("seq/frame_002.png")
        .mentions(&["<dir>/seq/frame_002.png", "not a regular file (a pipe)"]);
    dic_folder_dev_zero_entry: dic_folder(Case::run(DIC, &[])).file("seq/frame_000.png", png()).file("seq/frame_001.png", png())
        .symlink("seq/zero.png", "/dev/zero")
        .mentions(&["<dir>/seq/zero.png", "character device"]);
    contact_images_symlink_loop_entry: Case::run(CONTACT_IMAGES, &[])
        .file("seq/img_1_t1s.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n0.5,1.0\n")
        .symlink("seq/img_2_t2s.png", "<dir>/seq/img_2_t2s.png")
        .mentions(&["<dir>/seq/img_2_t2s.png", "symlink loop"]);
    contact_images_symlinked_folder_entry: Case::run(CONTACT_IMAGES, &[])
        .file("seq/img_1_t1s.png", png())
        .file("seq/force.csv", "time_s,force_n\n0.0,0.0\n0.5,1.0\n")
        .file("elsewhere/img_2_t2s.png", png())
        .symlink("seq/more", "<dir>/elsewhere")
        .mentions(&["<dir>/seq/more", "symlink to a folder, which is not followed"]);

    // #31 cache
    // Entries made by another build, or written before manifests named
    // their build, are listed by `verify --producer`, not taken silently
    // (#31, 4); the listing is no failure.
    cache_verify_producer_lists_other_and_unknown_builds: Case::new(&["cache", "verify", "--producer", "--cache", "<dir>/cache"])
        .file("cache/HYPERCONTACT_CACHE", "")
        .file("cache/entries/aaaa/manifest.json", old_manifest("aaaa", None))
        .file("cache/entries/bbbb/manifest.json", old_manifest("bbbb", Some("0.0.1+src.0123456789abcdef")))
        .exit(0);

    // #31 formats
    // A file no reader recognises is named for what its bytes are, not told
    // that a .npy holds no grid spacing (item 13).
    height_map_png_named_x3p: Case::run(&MAP.replace("path: map.npy, pixel_m: 20.0e-6", "path: map.x3p"), &[]).file("map.x3p", png())
        .mentions(&["map.x3p", "PNG image"])
        .lacks("holds no grid spacing");
    height_map_empty_sur: Case::run(&MAP.replace("path: map.npy, pixel_m: 20.0e-6", "path: map.sur"), &[]).file("map.sur", "")
        .mentions(&["map.sur", "empty"])
        .lacks("holds no grid spacing");
    height_map_text_named_plu: Case::run(&MAP.replace("path: map.npy, pixel_m: 20.0e-6", "path: map.plu"), &[]).file("map.plu", "x,y,z\n0,0,1\n")
        .mentions(&["map.plu", "not a Sensofar"])
        .lacks("holds no grid spacing");
    // A .npy is judged by its header before its data is read (item 6): a
    // 6 GB file whose header says 1 × 1 was read whole (6.2 GB RSS).
    height_map_npy_6_gb_promising_1x1: Case::run(MAP, &[]).file("map.npy", npy("<f8", "(1, 1)", &f64_bytes([1e-6]))).sparse("map.npy", 6_000_000_000)
        .mentions(&["map.npy", "shape (1, 1)", "the file holds 5999999872"]);
    // A header past the points limit is refused before allocation, saying
    // how to raise it (item 7).
    height_map_npy_beyond_max_points: Case::run(MAP, &[]).file("map.npy", npy("<f8", "(16384, 16384)", &f64_bytes([1e-6])))
        .mentions(&["map.npy", "(16384, 16384) = 268 435 456 points", "max_points"]);
    // A real .plu header before 4 GiB of holes is judged by its size
    // against the most a .plu of max_points points can be, unread (item
    // 6; before, read whole and accepted).
    height_map_plu_header_before_4_gib: Case::run(&MAP.replace("path: map.npy, pixel_m: 20.0e-6", "path: map.plu"), &[])
        .file("map.plu", &reference_plu()[..65536]).sparse("map.plu", 4 << 30)
        .mentions(&["map.plu", "is 4294967296 bytes", "max_points"]);
}
