//! Movies on a real Slurm: `render.sh --by frames --slurm-array DIR` and the commands the
//! README gives, submitted to a one-node cluster the test starts (`pipeline_tests::slurm`):
//! the array's tasks, and the check that runs after them however they ended. One task
//! made to fail, the check job names its frames and prints the line that submits it again;
//! that line, run, mends the movie, and every frame is then a local run's. The folder
//! holds a space and a quote.
//!
//! Where Slurm is not installed, the test says so and returns; under `CI=true` it fails
//! instead.

use pipeline_tests::slurm::Cluster;
use pipeline_tests::{bin, bin_dir, repo_root};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// The PNG files of a folder, by name.
fn pngs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "png"))
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p.file_name().unwrap().to_string_lossy().into_owned(), bytes)
        })
        .collect();
    files.sort();
    files
}

/// The job number sbatch printed (`Submitted batch job N`, or N with --parsable).
fn job_number(out: &std::process::Output) -> String {
    let text = String::from_utf8_lossy(&out.stdout);
    text.split_whitespace().last().unwrap_or("").to_string()
}

/// The text of the check job's log, DIR/check-N.out.
fn check_log(dir: &Path, job: &str) -> String {
    std::fs::read_to_string(dir.join(format!("check-{job}.out"))).unwrap_or_default()
}

#[test]
fn the_readmes_recipe_names_a_failed_task_and_its_resubmit_line_mends_it() {
    let Some(cluster) = Cluster::start() else {
        return;
    };
    bin_dir();
    let tmp = tempfile::tempdir().unwrap();
    let base = tmp.path().join("it's a movie");
    std::fs::create_dir_all(&base).unwrap();
    let movie = base.join("movie.pp");
    let scene = Command::new(bin("scene"))
        .args([
            "environment",
            "--frames",
            "60",
            "--polygons",
            "20",
            "--size",
            "32x32",
        ])
        .output()
        .unwrap();
    assert!(scene.status.success());
    std::fs::write(&movie, scene.stdout).unwrap();
    let here = base.join("here");
    std::fs::create_dir_all(&here).unwrap();
    let local = Command::new("bash")
        .arg(repo_root().join("scripts/render.sh"))
        .args(["--size", "32x32", "--depth", "0", "-o"])
        .arg(here.join("frame%05d.png"))
        .arg(&movie)
        .current_dir(repo_root())
        .output()
        .unwrap();
    assert!(
        local.status.success(),
        "{}",
        String::from_utf8_lossy(&local.stderr)
    );

    // The README's commands, with DIR the folder `out dir` of the movie's.
    let dir: PathBuf = base.join("out dir");
    let write = Command::new("bash")
        .arg(repo_root().join("scripts/render.sh"))
        .args(["--by", "frames", "--slurm-array"])
        .arg(&dir)
        .args(["--chunk", "10", "-o"])
        .arg(dir.join("frame%05d.png"))
        .args(["--size", "32x32", "--depth", "0"])
        .arg(&movie)
        .current_dir(repo_root())
        .output()
        .unwrap();
    assert!(
        write.status.success(),
        "{}",
        String::from_utf8_lossy(&write.stderr)
    );
    // Task 2 (frames 20 to 29) cannot write frame 25: a folder is in its place.
    std::fs::create_dir_all(dir.join("frame00025.png")).unwrap();
    let script = dir.join("render.sbatch");
    let array = cluster
        .command("sbatch")
        .arg("--parsable")
        .arg(&script)
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(
        array.status.success(),
        "{}",
        String::from_utf8_lossy(&array.stderr)
    );
    let jid = job_number(&array);
    let check = cluster
        .command("sbatch")
        .arg(format!("--dependency=afterany:{jid}"))
        .arg(dir.join("check.sbatch"))
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    let cid = job_number(&check);
    cluster.wait_idle(Duration::from_secs(60));

    let log = check_log(&dir, &cid);
    let quoted = format!("'{}'", script.display().to_string().replace('\'', r"'\''"));
    let resubmit = format!("sbatch --array=2 {quoted}");
    assert!(
        log.contains(&format!(
            "frame 25 ({}): not a file\n",
            dir.join("frame00025.png").display()
        )) && log.contains(&format!("\n{resubmit}\n"))
            && log.ends_with(
                "frames missing or bad, of array task 2: the line above submits it again\n"
            ),
        "the check job's log:\n{log}\n{}",
        cluster.logs()
    );
    // Every log is in DIR: the tasks' and the check's.
    let logs = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".out"))
        .count();
    assert_eq!(logs, 7, "six tasks' logs and the check's");

    // The line printed, run as it is, once the folder in frame 25's place is gone.
    std::fs::remove_dir(dir.join("frame00025.png")).unwrap();
    let again = cluster
        .command("bash")
        .arg("-c")
        .arg(&resubmit)
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    cluster.wait_idle(Duration::from_secs(60));
    let checked = Command::new("bash")
        .arg(&script)
        .arg("--check")
        .output()
        .unwrap();
    assert!(
        checked.status.success(),
        "{}{}",
        String::from_utf8_lossy(&checked.stdout),
        String::from_utf8_lossy(&checked.stderr)
    );
    assert_eq!(
        String::from_utf8_lossy(&checked.stdout),
        "all 60 frames there, whole\n"
    );
    let ours = pngs(&dir);
    assert_eq!(ours.len(), 60);
    assert!(
        ours == pngs(&here),
        "the array's frames differ from a local run's"
    );
}
