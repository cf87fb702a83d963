//! `scripts/slurm/render-array.sh` on a real single-node Slurm started here: munged, slurmctld
//! and slurmd with a private key, socket, ports and folders; an array job of 4 parts and the
//! dependent merge give the image of one render, bit for bit. Skips, with a message, where Slurm
//! and munge are not installed (Debian: `apt-get install slurm-wlm munge`; `.ci/run` does) or
//! cannot start; stops the daemons it started.

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use foton::film::read_exr;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell.lxs");
const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/slurm/render-array.sh");

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|p| p.join(program).is_file()))
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// The daemons this test started, stopped (by the pids they wrote) when dropped.
struct Cluster {
    dir: PathBuf,
    started: Vec<PathBuf>,
}

impl Cluster {
    fn command(&self, program: &str) -> Command {
        let mut command = Command::new(program);
        command.env("SLURM_CONF", self.dir.join("slurm.conf"));
        command
    }

    /// Starts a daemon that forks and writes `pid_file`; false if it did not start.
    fn start(&mut self, program: &str, args: &[&str], pid_file: &str) -> bool {
        let output = self.command(program).args(args).output();
        let pid = self.dir.join(pid_file);
        let deadline = Instant::now() + Duration::from_secs(10);
        while !pid.exists() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(100));
        }
        if pid.exists() {
            self.started.push(pid);
            true
        } else {
            eprintln!("{program} did not start: {:?}", output.map(|o| text(&o)));
            false
        }
    }

    fn log(&self) -> String {
        ["slurmctld.log", "slurmd.log"]
            .iter()
            .map(|l| std::fs::read_to_string(self.dir.join(l)).unwrap_or_default())
            .collect::<Vec<_>>()
            .join("\n")
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        for pid in self.started.iter().rev() {
            if let Ok(pid) = std::fs::read_to_string(pid) {
                let _ = Command::new("kill").arg(pid.trim()).status();
            }
        }
    }
}

/// A private single-node cluster in `dir`, or why it could not start.
fn start_cluster(dir: &Path) -> Result<Cluster, String> {
    let host = Command::new("hostname")
        .arg("-s")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .map_err(|e| format!("hostname: {e}"))?;
    let user = Command::new("id")
        .arg("-un")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .map_err(|e| format!("id: {e}"))?;
    let key_path = dir.join("munge.key");
    let random = Command::new("dd")
        .args(["if=/dev/urandom", "bs=1024", "count=1"])
        .arg(format!("of={}", key_path.display()))
        .output()
        .map_err(|e| format!("dd: {e}"))?;
    if !random.status.success() {
        return Err(text(&random));
    }
    let mode = |p: &Path, m: u32| std::fs::set_permissions(p, std::fs::Permissions::from_mode(m));
    mode(&key_path, 0o400).map_err(|e| e.to_string())?;
    mode(dir, 0o700).map_err(|e| e.to_string())?;
    for sub in ["state", "spool"] {
        std::fs::create_dir_all(dir.join(sub)).map_err(|e| e.to_string())?;
    }
    // Ports of this process's own, away from Slurm's defaults (6817, 6818).
    let port = 20_000 + (std::process::id() % 20_000) * 2;
    let d = dir.display();
    let conf = format!(
        "ClusterName=foton\nSlurmctldHost={host}\nSlurmUser={user}\nSlurmctldPort={port}\n\
         SlurmdPort={}\nAuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket={d}/munge.sock\n\
         StateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\nSlurmctldPidFile={d}/slurmctld.pid\n\
         SlurmdPidFile={d}/slurmd.pid\nSlurmctldLogFile={d}/slurmctld.log\n\
         SlurmdLogFile={d}/slurmd.log\nProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n\
         SchedulerType=sched/backfill\nSelectType=select/cons_tres\nReturnToService=2\n\
         NodeName={host} CPUs=2 State=UNKNOWN\n\
         PartitionName=main Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
        port + 1
    );
    std::fs::write(dir.join("slurm.conf"), conf).map_err(|e| e.to_string())?;
    let mut cluster = Cluster {
        dir: dir.to_path_buf(),
        started: Vec::new(),
    };
    let munge_args = [
        "--force".to_string(),
        format!("--socket={d}/munge.sock"),
        format!("--key-file={d}/munge.key"),
        format!("--pid-file={d}/munged.pid"),
        format!("--log-file={d}/munged.log"),
        format!("--seed-file={d}/munge.seed"),
    ];
    let munge_args: Vec<&str> = munge_args.iter().map(String::as_str).collect();
    let started = cluster.start("munged", &munge_args, "munged.pid")
        && cluster.start("slurmctld", &[], "slurmctld.pid")
        && cluster.start("slurmd", &[], "slurmd.pid");
    if !started {
        return Err(format!("the daemons did not start\n{}", cluster.log()));
    }
    // The node is up when sinfo says it is idle.
    let deadline = Instant::now() + Duration::from_secs(30);
    while Instant::now() < deadline {
        let sinfo = cluster.command("sinfo").args(["-h", "-o", "%T"]).output();
        if sinfo.is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("idle")) {
            return Ok(cluster);
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    Err(format!("the node did not come up\n{}", cluster.log()))
}

#[test]
fn slurm_array_job_merges_to_one_render() {
    let missing: Vec<&str> = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"]
        .into_iter()
        .filter(|p| !on_path(p))
        .collect();
    if !missing.is_empty() {
        eprintln!(
            "skipped: Slurm is not installed ({} not found; apt-get install slurm-wlm munge)",
            missing.join(", ")
        );
        return;
    }
    let dir = std::env::temp_dir().join(format!("foton-slurm-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let cluster = match start_cluster(&dir) {
        Ok(cluster) => cluster,
        Err(why) => {
            eprintln!("skipped: a local Slurm could not start: {why}");
            return;
        }
    };
    let settings = ["--resolution", "40x28", "--seed", "3"];
    let full = dir.join("full.exr");
    let output = Command::new(env!("CARGO_BIN_EXE_foton"))
        .args(["render", SCENE, "--quiet", "--spp", "8", "-o"])
        .arg(&full)
        .args(settings)
        .output()
        .expect("foton runs");
    assert!(output.status.success(), "{}", text(&output));
    let merged = dir.join("merged.exr");
    let output = cluster
        .command("bash")
        .arg(SCRIPT)
        .args([SCENE, merged.to_str().expect("UTF-8"), "8", "4"])
        .args(settings)
        .env("FOTON", env!("CARGO_BIN_EXE_foton"))
        .output()
        .expect("bash runs");
    assert!(output.status.success(), "{}", text(&output));
    assert!(text(&output).contains("4 tasks"), "{}", text(&output));
    // Bounded: the array and the merge ran in seconds where measured.
    let deadline = Instant::now() + Duration::from_secs(180);
    loop {
        let queue = cluster.command("squeue").args(["-h"]).output();
        let empty = queue.is_ok_and(|o| o.status.success() && o.stdout.is_empty());
        if empty && merged.exists() {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the jobs did not finish in 180 s\n{}\n{}",
            std::fs::read_to_string(dir.join("merged.exr.parts/merge.log")).unwrap_or_default(),
            cluster.log()
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    let parts = std::fs::read_dir(dir.join("merged.exr.parts"))
        .expect("the parts folder")
        .filter(|e| {
            e.as_ref()
                .is_ok_and(|e| e.path().extension().is_some_and(|x| x == "exr"))
        })
        .count();
    assert_eq!(parts, 4);
    let bits = |p: &Path| -> Vec<[u32; 3]> {
        read_exr(p)
            .expect("an EXR")
            .2
            .iter()
            .map(|v| v.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(
        bits(&merged),
        bits(&full),
        "the Slurm-merged image is not the render's"
    );
    drop(cluster);
}
