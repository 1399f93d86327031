//! Grading on a cluster (issue 47, found 7; docs/grading.md §"More submissions than one machine
//! handles"): the Slurm recipe's task script, as the docs give it, run once per array task, and
//! the merge of the tasks' reports.

use crate::common;

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::process::Command;

/// The task script and the merge command of docs/grading.md's recipe: the indented block that
/// starts with `#!/bin/bash`, and the command `sbatch --wrap` runs.
fn recipe() -> (String, String) {
    let docs = std::fs::read_to_string(common::project_root().join("docs/grading.md")).unwrap();
    let lines: Vec<&str> = docs.lines().collect();
    let start = lines
        .iter()
        .position(|l| *l == "    #!/bin/bash")
        .expect("docs/grading.md gives the task script");
    let script: Vec<&str> = lines[start..]
        .iter()
        .take_while(|l| l.starts_with("    "))
        .map(|l| &l[4..])
        .collect();
    let wrap = lines
        .iter()
        .find_map(|l| l.split_once("--wrap \"").map(|(_, rest)| rest))
        .expect("docs/grading.md gives the merge");
    let merge = wrap.trim_end().trim_end_matches('"').to_string();
    (script.join("\n") + "\n", merge)
}

/// Runs the task script in `dir` as task `k` of an array of `n`, with rigidref on the PATH.
fn task(dir: &Path, script: &Path, k: usize, n: usize) -> std::process::Output {
    let bin = common::rigidref_bin();
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    Command::new("bash")
        .arg(script)
        .current_dir(dir)
        .env("PATH", path)
        .env("SLURM_ARRAY_TASK_ID", k.to_string())
        .env("SLURM_ARRAY_TASK_COUNT", n.to_string())
        .env("SLURM_CPUS_PER_TASK", "1")
        .output()
        .unwrap()
}

/// Every task of an array of `n`, then the merge (in bash, as `sbatch --wrap` runs it, the
/// reports' glob expanded there). Returns the merge's output.
fn array(dir: &Path, script: &Path, merge: &str, n: usize) -> std::process::Output {
    for k in 1..=n {
        let o = task(dir, script, k, n);
        assert!(
            o.status.success(),
            "task {k} of {n}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            common::stderr(&o)
        );
    }
    merge_only(dir, merge)
}

fn merge_only(dir: &Path, merge: &str) -> std::process::Output {
    let bin = common::rigidref_bin();
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    Command::new("bash")
        .args(["-c", merge])
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .unwrap()
}

/// The merged report's verdict per submission, from report/grade.csv (names as the table shows
/// them) and the number of rows per submission and scene.
fn merged(dir: &Path) -> Vec<(String, String)> {
    let mut reader = csv::Reader::from_path(dir.join("report/grade.csv")).unwrap();
    let rows: Vec<Vec<String>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    let mut names: Vec<String> = rows.iter().map(|r| r[0].clone()).collect();
    names.dedup();
    names
        .into_iter()
        .map(|n| {
            let mine: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == n).collect();
            let verdict = if mine.iter().any(|r| r[3] != "pass") {
                mine.iter().find(|r| r[3] != "pass").unwrap()[3].clone()
            } else {
                "pass".into()
            };
            (n, verdict)
        })
        .collect()
}

/// The recipe, run as Slurm runs it (docs/grading.md §"More submissions than one machine
/// handles"): five submissions, named with a space, a quote, a byte that is not UTF-8 (two that
/// differ only there, one cut at half time) and plain ASCII, graded by an array of 2 tasks and
/// merged: each graded once, with its own verdict. An array of 7 (longer than the list) gives the same table, the
/// tasks without a share writing empty reports. A student added after the array ran: the merge
/// of the old reports names the new student as graded by no shard (exit 1); the array run again
/// grades everyone. A report of an earlier, longer array left among the reports, and one shard's
/// report given twice, are refused, naming them.
#[test]
fn the_slurm_recipe_grades_every_submission_once_whatever_its_name() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (script_text, merge) = recipe();
    assert!(
        script_text.contains("--shard \"$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT\""),
        "{script_text}"
    );
    assert!(
        merge.starts_with("rigidref grade submissions --merge reports/*"),
        "{merge}"
    );
    let script = dir.join("grade-task.sh");
    std::fs::write(&script, &script_text).unwrap();
    // The scene: the projectile (a scene file and its body files under scenes/).
    let root = common::project_root();
    std::fs::create_dir_all(dir.join("scenes/data")).unwrap();
    std::fs::copy(
        root.join("scenes/projectile.json"),
        dir.join("scenes/projectile.json"),
    )
    .unwrap();
    for file in ["block.json", "block.obj"] {
        std::fs::copy(
            root.join("scenes/data").join(file),
            dir.join("scenes/data").join(file),
        )
        .unwrap();
    }
    let o = common::rigidref(
        &[
            "run",
            "scenes/projectile.json",
            "--time",
            "5",
            "-q",
            "--out",
            "ref.jsonl",
        ],
        dir,
    );
    common::assert_success(&o);
    // A trace that stops at half time: refused.
    let text = std::fs::read_to_string(dir.join("ref.jsonl")).unwrap();
    let half: Vec<&str> = text.lines().take(250).collect();
    std::fs::write(dir.join("cut.jsonl"), half.join("\n") + "\n").unwrap();
    let add = |name: &[u8], trace: &str| {
        let folder = dir.join("submissions").join(OsStr::from_bytes(name));
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::copy(dir.join(trace), folder.join("projectile.jsonl")).unwrap();
    };
    add(b"ada lovelace", "ref.jsonl");
    add(b"o'brien", "ref.jsonl");
    add(b"jos\xe9", "ref.jsonl");
    add(b"jos\xe8", "cut.jsonl");
    add(b"zed", "ref.jsonl");
    let expected = |extra: &[(&str, &str)]| -> Vec<(String, String)> {
        let mut all = vec![
            ("ada lovelace", "pass"),
            ("jos\\xe8", "refused"),
            ("jos\\xe9", "pass"),
            ("o'brien", "pass"),
            ("zed", "pass"),
        ];
        all.extend_from_slice(extra);
        all.sort();
        all.into_iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    };
    let o = array(dir, &script, &merge, 2);
    common::assert_success(&o);
    assert_eq!(merged(dir), expected(&[]));
    // An array longer than the list: the same table; two tasks had nothing to grade.
    std::fs::remove_dir_all(dir.join("reports")).unwrap();
    let o = array(dir, &script, &merge, 7);
    common::assert_success(&o);
    assert_eq!(merged(dir), expected(&[]));
    let empty = std::fs::read_to_string(dir.join("reports/7/grade.csv")).unwrap();
    assert_eq!(empty, "submission,scene,observable,result,figure\n");
    // A student added after the array ran: the old reports miss her, by name.
    add(b"new student", "ref.jsonl");
    let o = merge_only(dir, &merge);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("1 of 6 submissions graded by no shard: \"new student\""),
        "{}",
        common::stderr(&o)
    );
    // Run again (the recipe removes the old reports first): everyone, once.
    std::fs::remove_dir_all(dir.join("reports")).unwrap();
    let o = array(dir, &script, &merge, 3);
    common::assert_success(&o);
    assert_eq!(merged(dir), expected(&[("new student", "pass")]));
    // A report of an earlier run of 7 tasks left beside these 3: refused, naming it.
    std::fs::create_dir_all(dir.join("reports/7")).unwrap();
    let o = task(dir, &script, 7, 7);
    common::assert_success(&o);
    let o = merge_only(dir, &merge);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("reports/7 is shard 7 of 7")
            && common::stderr(&o).contains("not shards of one run"),
        "{}",
        common::stderr(&o)
    );
    std::fs::remove_dir_all(dir.join("reports/7")).unwrap();
    // One shard's report twice.
    let copy = Command::new("cp")
        .args(["-r", "reports/2", "reports/2-again"])
        .current_dir(dir)
        .status()
        .unwrap();
    assert!(copy.success());
    let o = merge_only(dir, &merge);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        common::stderr(&o).contains("shard 2 of 3 is in both reports/2 and reports/2-again"),
        "{}",
        common::stderr(&o)
    );
}
