//! A sweep's runs as processes: a killed sweep resumed (completed runs
//! skipped, changed ones refused), and shards run as separate processes then
//! collected into the whole sweep.

use crate::cli_common::*;
use crate::cli_sweep::{folders, sweep_table};
use std::path::Path;

fn record_status(run_dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(run_dir.join("sweep-run.json")).ok()?;
    let value: serde_json::Value = serde_json::from_str(&text).ok()?;
    value["status"].as_str().map(String::from)
}

/// Whether a process other than this one has `dir` (or a folder under it) as
/// its working directory or names it on its command line: a sweep's run
/// outliving the sweep. (Linux's /proc; elsewhere no process is seen.)
fn a_process_works_in(dir: &Path) -> bool {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return false;
    };
    let me = std::process::id().to_string();
    let needle = dir.to_string_lossy().into_owned();
    entries.flatten().any(|entry| {
        let pid = entry.file_name();
        if pid.to_string_lossy() == me || !pid.to_string_lossy().bytes().all(|b| b.is_ascii_digit())
        {
            return false;
        }
        let proc_dir = entry.path();
        let in_dir = std::fs::read_link(proc_dir.join("cwd")).is_ok_and(|cwd| cwd.starts_with(dir));
        let names_it = std::fs::read(proc_dir.join("cmdline"))
            .is_ok_and(|cmdline| String::from_utf8_lossy(&cmdline).contains(&needle));
        in_dir || names_it
    })
}

#[test]
fn a_killed_sweep_resumes_skipping_completed_runs_and_refuses_changed_ones() {
    let tmp = tempfile::tempdir().unwrap();
    let args = [
        "sweep",
        "report-drop-2d",
        "--vary",
        "material.young=100,200,300,400",
        "--frames",
        "400",
        "--no-render",
        "--out",
        "resume",
        "--jobs",
        "1",
        "-q",
    ];
    let mut child = crate::cli_common::elasto_command()
        .args(args)
        .current_dir(tmp.path())
        .spawn()
        .unwrap();
    let dir = tmp.path().join("resume");
    let first = dir.join("0000_material.young=100");
    let runs = [
        first.clone(),
        dir.join("0001_material.young=200"),
        dir.join("0002_material.young=300"),
        dir.join("0003_material.young=400"),
    ];
    wait_until(
        "the first run completes",
        std::time::Duration::from_secs(120),
        || {
            assert!(
                child.try_wait().unwrap().is_none(),
                "the sweep ended before it was killed"
            );
            record_status(&first).as_deref() == Some("ok")
        },
    );
    child.kill().unwrap();
    child.wait().unwrap();
    let first_stats = std::fs::read(first.join("stats.csv")).unwrap();
    let modified = std::fs::metadata(first.join("stats.csv"))
        .unwrap()
        .modified()
        .unwrap();
    // The sweep writes the records and has exited; its run, sent SIGTERM
    // when the sweep died, is waited for (not a fixed time) so that nothing
    // still writes into the folder when it is checked and resumed.
    wait_until(
        "the killed sweep's run process exits",
        std::time::Duration::from_secs(60),
        || !a_process_works_in(tmp.path()),
    );
    // How far the sweep got before the kill landed is the scheduler's: the
    // first run at least, in order, never all four (each run takes about
    // 0.4 s, the wait above looks every 10 ms). The run that was going has
    // no completion marker.
    let complete: Vec<bool> = runs
        .iter()
        .map(|run| record_status(run).as_deref() == Some("ok"))
        .collect();
    let done = complete.iter().take_while(|c| **c).count();
    assert!(
        (1..4).contains(&done) && complete[done..].iter().all(|c| !c),
        "{complete:?}"
    );
    assert!(
        !dir.join("sweep.csv").exists(),
        "the killed sweep did not finish"
    );
    // What a kill while a run folder is being made leaves: the hidden
    // staging folder with a half-written record, never a run folder
    // without its record (which the resumed sweep would refuse).
    let staging = dir.join(".0003_material.young=400.partial");
    std::fs::create_dir_all(&staging).unwrap();
    std::fs::write(staging.join(".sweep-run.json.partial"), "{ \"ind").unwrap();
    for run in std::fs::read_dir(&dir).unwrap() {
        let run = run.unwrap().path();
        let name = run.file_name().unwrap().to_string_lossy().into_owned();
        if !name.starts_with('.') {
            assert!(record_status(&run).is_some(), "{name} has no record");
        }
    }

    let o = elasto(tmp.path(), &args[..args.len() - 1]);
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains(&format!("{done} of 4 runs already complete, skipped")),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(first.join("stats.csv")).unwrap(), first_stats);
    assert!(
        !staging.exists(),
        "the stale staging folder was not cleared"
    );
    assert_eq!(
        std::fs::metadata(first.join("stats.csv"))
            .unwrap()
            .modified()
            .unwrap(),
        modified,
        "the completed run was not redone"
    );
    let table = sweep_table(&dir);
    assert!(
        table
            .iter()
            .all(|r| r["status"] == "ok" && r["frames"] == "400"),
        "{table:?}"
    );

    // Same folders, other parameters: an error naming the folder; --force redoes.
    let mut changed = args.to_vec();
    changed[5] = "30";
    let o = elasto(tmp.path(), &changed);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("0000_material.young=100 holds a run with other parameters"),
        "{}",
        stderr(&o)
    );
    changed.push("--force");
    let o = elasto(tmp.path(), &changed);
    assert_code(&o, 0);
    assert!(sweep_table(&dir).iter().all(|r| r["frames"] == "30"));
}

/// Four shards run as four processes at once (as GNU parallel or a Slurm
/// array would start them), then `--collect` gathers the whole sweep.
#[test]
fn shards_run_as_separate_processes_and_collect_into_the_whole_sweep() {
    let tmp = tempfile::tempdir().unwrap();
    let common = "sweep report-drop-2d --vary material.young=100,300,1000 --vary time.substeps=1,2 \
                  --frames 3 --no-render -q";
    let args: Vec<&str> = common.split(' ').collect();
    let mut whole = args.clone();
    whole.extend(["--out", "whole"]);
    assert_code(&elasto(tmp.path(), &whole), 0);

    let shards: Vec<std::process::Child> = (0..4)
        .map(|i| {
            crate::cli_common::elasto_command()
                .args(&args)
                .args(["--out", "sharded", "--shard", &format!("{i}/4")])
                .current_dir(tmp.path())
                .env_remove("RUST_BACKTRACE")
                .stdin(std::process::Stdio::null())
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("the elasto binary starts")
        })
        .collect();
    for (i, shard) in shards.into_iter().enumerate() {
        let o = shard.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(0), "shard {i}/4: {}", stderr(&o));
    }
    let sharded = tmp.path().join("sharded");
    assert!(
        !sharded.join("sweep.csv").exists(),
        "shards leave the table to --collect"
    );
    assert_eq!(folders(&sharded), folders(&tmp.path().join("whole")));
    let mut collect = args.clone();
    collect.extend(["--out", "sharded", "--collect"]);
    assert_code(&elasto(tmp.path(), &collect), 0);

    let strip = |dir: &Path| -> Vec<Vec<(String, String)>> {
        sweep_table(dir)
            .into_iter()
            .map(|row| {
                row.into_iter()
                    .filter(|(k, _)| k != "wall_seconds")
                    .collect()
            })
            .collect()
    };
    let whole_table = strip(&tmp.path().join("whole"));
    assert_eq!(whole_table.len(), 6);
    assert_eq!(strip(&sharded), whole_table);

    // A shard alone runs only its runs; --collect then reports the rest as not run.
    let mut one_shard = args.clone();
    one_shard.extend(["--out", "partial", "--shard", "1/4"]);
    assert_code(&elasto(tmp.path(), &one_shard), 0);
    assert_eq!(
        folders(&tmp.path().join("partial")),
        [
            "0001_material.young=100_time.substeps=2",
            "0005_material.young=1000_time.substeps=2"
        ]
    );
    let mut collect = args.clone();
    collect.extend(["--out", "partial", "--collect"]);
    let o = elasto(tmp.path(), &collect);
    assert_code(&o, 1);
    let status: Vec<String> = sweep_table(&tmp.path().join("partial"))
        .into_iter()
        .map(|r| r["status"].clone())
        .collect();
    assert_eq!(
        status,
        ["skipped", "ok", "skipped", "skipped", "skipped", "ok"]
    );
}
