//! The `kea` command: output and exit codes.

use std::process::Command;

fn kea(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_kea"))
        .args(args)
        .output()
        .expect("kea runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn scene(name: &str) -> String {
    format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn run_prints_a_summary_and_writes_trajectories() {
    let dir = std::env::temp_dir().join(format!("kea-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("drop.csv");
    let json = dir.join("drop.json");
    let (code, out, err) = kea(&[
        "run",
        &scene("drop.json"),
        "--steps",
        "30",
        "--csv",
        csv.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for word in ["30 steps", "steps/s", "awake", "energy", "warnings"] {
        assert!(out.contains(word), "missing {word:?} in {out}");
    }
    let csv = std::fs::read_to_string(csv).unwrap();
    assert_eq!(csv.lines().count(), 1 + 31, "header + the start + 30 steps");
    assert!(csv.starts_with("t,body,x,y,z"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    assert_eq!(json.as_array().unwrap().len(), 31);
    // The box falls: its last height is below its first.
    let y = |row: &serde_json::Value| row["position"][1].as_f64().unwrap();
    assert!(y(&json[30]) < y(&json[0]));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn run_without_a_scene_uses_the_embedded_pyramid() {
    let (code, out, err) = kea(&["run", "--steps", "5"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("embedded pyramid") && out.contains("210 awake"),
        "{out}"
    );
}

#[test]
fn bench_prints_one_machine_readable_line_per_scene() {
    let (code, out, err) = kea(&[
        "bench",
        &scene("drop.json"),
        &scene("pyramid.json"),
        "--steps",
        "20",
        "--repeats",
        "3",
    ]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out}");
    for line in &lines {
        let value = |key: &str| -> f64 {
            line.split(' ')
                .find_map(|kv| kv.strip_prefix(&format!("{key}=")[..]))
                .unwrap_or_else(|| panic!("no {key} in {line}"))
                .parse()
                .unwrap()
        };
        assert!(line.starts_with("scene="), "{line}");
        assert_eq!(value("repeats"), 3.0, "{line}");
        let (mid, min, max) = (value("ms_per_step"), value("min_ms"), value("max_ms"));
        assert!(0.0 < min && min <= mid && mid <= max, "{line}");
        assert!(value("spread_pct") >= 0.0, "{line}");
        // The collision stage is its broad and narrow phases, and part of the step.
        let collision = value("collision_ms");
        assert!(
            collision >= value("broad_ms") && collision >= value("narrow_ms"),
            "{line}"
        );
        assert!(collision <= max, "{line}");
    }
    // The pyramid's 210 boxes spend real time in collision.
    let pyramid = lines[1];
    assert!(pyramid.contains("pyramid.json"), "{pyramid}");
    assert!(!pyramid.contains(" collision_ms=0.0000"), "{pyramid}");

    let (code, _, err) = kea(&["bench", &scene("drop.json"), "--repeats", "0"]);
    assert_eq!(code, 1);
    assert!(err.contains("--repeats 0"), "{err}");
}

#[test]
fn failures_exit_non_zero_with_a_message_and_write_nothing() {
    let dir = std::env::temp_dir().join(format!("kea-cli-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        "{\"version\": 1,\n \"bodies\": [{\"name\": \"a\", \"mass\": -1, \"position\": [0,0,0]}]}",
    )
    .unwrap();
    let csv = dir.join("out.csv");
    let (code, _, err) = kea(&["run", bad.to_str().unwrap(), "--csv", csv.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("bodies[0].mass"), "{err}");
    assert!(!csv.exists(), "nothing is written on failure");
    let (code, _, err) = kea(&["run", "/no/such/scene.json"]);
    assert_eq!(code, 1);
    assert!(err.contains("/no/such/scene.json"), "{err}");
    let (code, _, err) = kea(&["run", &scene("drop.json"), "--steps", "0"]);
    assert_eq!(code, 1);
    assert!(err.contains("--steps"), "{err}");
    let (code, _, _) = kea(&["frobnicate"]);
    assert_eq!(code, 2, "clap's usage error");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn render_writes_a_png_of_the_scene() {
    let dir = std::env::temp_dir().join(format!("kea-cli-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("drop.png");
    let (code, out, err) = kea(&[
        "render",
        &scene("drop.json"),
        "--out",
        png.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("64×48"), "{out}");
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "a PNG file");
    // Width and height sit in the IHDR chunk, big-endian, right after the signature.
    assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 64);
    assert_eq!(u32::from_be_bytes(bytes[20..24].try_into().unwrap()), 48);
    let (code, _, err) = kea(&["render", &scene("drop.json"), "--out", "frame.bmp"]);
    assert_eq!(code, 1);
    assert!(err.contains(".png or a .gif"), "{err}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn render_writes_an_animated_gif() {
    let dir = std::env::temp_dir().join(format!("kea-cli-gif-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let gif = dir.join("drop.gif");
    let (code, out, err) = kea(&[
        "render",
        &scene("drop.json"),
        "--out",
        gif.to_str().unwrap(),
        "--frames",
        "5",
        "--every",
        "6",
        "--width",
        "40",
        "--height",
        "30",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("5 frames"), "{out}");
    let bytes = std::fs::read(&gif).unwrap();
    assert_eq!(&bytes[..6], b"GIF89a");
    assert_eq!(u16::from_le_bytes([bytes[6], bytes[7]]), 40);
    assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 30);
    // One image descriptor (0x2C after a graphic control block) per frame.
    let frames = bytes
        .windows(2)
        .filter(|w| w[0] == 0x00 && w[1] == 0x2C)
        .count();
    assert!(frames >= 5, "found {frames} image descriptors");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn render_drives_the_car_with_throttle_and_steer_and_frames_what_focus_names() {
    let dir = std::env::temp_dir().join(format!("kea-cli-drive-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let car = scene("car.json");
    let frame = |name: &str, extra: &[&str]| {
        let png = dir.join(name);
        let mut args = vec!["render", &car, "--out", png.to_str().unwrap()];
        args.extend(["--steps", "60", "--width", "48", "--height", "36"]);
        args.extend(extra);
        let (code, out, err) = kea(&args);
        assert_eq!(code, 0, "{extra:?}: {err}");
        assert!(out.contains("48×36"), "{out}");
        std::fs::read(png).unwrap()
    };
    // Forwards, backwards and the scene's own motors leave the car in three places.
    let forwards = frame("forwards.png", &["--throttle", "1"]);
    let backwards = frame("backwards.png", &["--throttle", "-1", "--steer", "-0.5"]);
    let own = frame("own.png", &[]);
    assert!(forwards != backwards && forwards != own && backwards != own);
    // Bad values are refused before any work, naming the option and the value.
    for (flag, value, words) in [
        (
            "--throttle",
            "NaN",
            "--throttle must be a number from -1 to 1, got NaN",
        ),
        (
            "--throttle",
            "1.5",
            "--throttle must be a number from -1 to 1, got 1.5",
        ),
        (
            "--steer",
            "-2",
            "--steer must be a number from -1 to 1, got -2",
        ),
        (
            "--steer",
            "inf",
            "--steer must be a number from -1 to 1, got inf",
        ),
    ] {
        let png = dir.join("refused.png");
        let args = ["render", &car, "--out", png.to_str().unwrap(), flag, value];
        let (code, _, err) = kea(&args);
        assert_eq!(code, 1, "{flag} {value}");
        assert!(err.contains(words), "{flag} {value}: {err}");
        assert!(!png.exists());
    }
    // A scene without a car has nothing to drive; `--focus` names bodies that exist.
    let png = dir.join("refused.png");
    let out = png.to_str().unwrap();
    let (code, _, err) = kea(&[
        "render",
        &scene("drop.json"),
        "--out",
        out,
        "--throttle",
        "1",
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("--throttle") && err.contains("no car-wheel joint"),
        "{err}"
    );
    let (code, _, err) = kea(&["render", &car, "--out", out, "--focus", "chasis"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("--focus chasis") && err.contains("no body named"),
        "{err}"
    );
    // Framed on one wheel, the picture is not the one framed on the whole car.
    let wheel = frame("wheel.png", &["--focus", "wheel_fl"]);
    assert_ne!(wheel, own);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn plot_draws_energy_momentum_gap_and_penetration_curves_with_the_legend_beside() {
    let dir = std::env::temp_dir().join(format!("kea-cli-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("pendulum.png");
    let (code, out, err) = kea(&[
        "plot",
        &scene("pendulum.json"),
        "--out",
        png.to_str().unwrap(),
        "--steps",
        "120",
        "--width",
        "400",
        "--height",
        "600",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("400×600"), "{out}");
    let decoder = png::Decoder::new(std::fs::File::open(&png).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (400, 600));
    // The two curve colours appear: the lines were drawn, not only the axes.
    let pixels: Vec<&[u8]> = buf[..info.buffer_size()].chunks(3).collect();
    for colour in [[200u8, 60, 40], [40, 90, 200]] {
        let n = pixels.iter().filter(|p| **p == colour).count();
        assert!(n > 100, "{colour:?}: {n} pixels");
    }
    // With labels, each chart's legend has its own column on the right: the only curve
    // colours there are the legend's swatches (x 6–30 of the column), never a curve or a
    // legend box over the data.
    if !out.contains("without labels") {
        let legend_x = 400 - 400 / 3;
        for (i, p) in pixels.iter().enumerate() {
            let x = (i % 400) as u32;
            let curve = *p == [200u8, 60, 40] || *p == [40, 90, 200];
            if curve && x >= legend_x {
                assert!(
                    (legend_x + 5..=legend_x + 31).contains(&x),
                    "curve colour at x = {x}, y = {} in the legend column",
                    i / 400
                );
            }
        }
    }
    let bad = dir.join("plot.gif");
    let (code, _, err) = kea(&[
        "plot",
        &scene("pendulum.json"),
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains(".png"), "{err}");
    assert!(!bad.exists(), "nothing written on error");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn outputs_are_written_all_or_none() {
    let dir = std::env::temp_dir().join(format!("kea-cli-outputs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("drop.csv");
    let missing = dir.join("no-such-folder").join("drop.json");
    let (code, _, err) = kea(&[
        "run",
        &scene("drop.json"),
        "--steps",
        "5",
        "--csv",
        csv.to_str().unwrap(),
        "--json",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("--json") && err.contains("does not exist"),
        "{err}"
    );
    assert!(
        !csv.exists(),
        "the CSV must not be written when the JSON cannot be"
    );
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // A scene whose energy overflows has nothing to plot: an error, no file (in f32 the
    // gravity itself is out of range and refused where the file says it; in f64 the body
    // blows up and is quarantined).
    let blowup = dir.join("blowup.json");
    std::fs::write(
        &blowup,
        r#"{"version": 1, "world": {"gravity": [0, -1e300, 0]},
            "bodies": [{"name": "b", "mass": 1, "position": [0, 0, 0]}]}"#,
    )
    .unwrap();
    let png = dir.join("blowup.png");
    let (code, _, err) = kea(&[
        "plot",
        blowup.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
        "--steps",
        "5",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("nothing to plot") || err.contains("gravity") || err.contains("out of range"),
        "{err}"
    );
    assert!(!png.exists());
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn run_with_dt_30_blows_up_and_exits_non_zero_unless_kept_going() {
    // Issue 12: `--dt 10` used to end with status 0 and an energy of −1.8e9 J. Since worlds
    // grow instead of dropping contacts (issue 13), the pyramid at 10 s steps only gains energy
    // without a runaway; 30 s steps run away within three steps.
    let (code, out, err) = kea(&["run", "--dt", "30", "--steps", "100"]);
    assert_eq!(code, 1, "{out}\n{err}");
    assert!(err.contains("blew up at step"), "{err}");
    assert!(err.contains("bodies quarantined"), "{err}");
    assert!(err.contains("pyramid0."), "bodies are named: {err}");
    assert!(err.contains("--keep-going"), "{err}");
    // Kea's warnings are said (once per kind), not only counted.
    assert!(err.contains("warning: kea:"), "{err}");
    let (code, out, err) = kea(&["run", "--dt", "30", "--steps", "100", "--keep-going"]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(err.contains("kept going"), "{err}");
    assert!(out.contains("bodies quarantined"), "{out}");
}

#[test]
fn an_interrupted_csv_run_leaves_no_partial_file() {
    let dir = std::env::temp_dir().join(format!("kea-cli-int-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("long.csv");
    let partial = dir.join("long.csv.kea-partial");
    let mut child = Command::new(env!("CARGO_BIN_EXE_kea"))
        .args(["run", "--steps", "1000000", "--csv"])
        .arg(&csv)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Wait until the run is writing, then press Ctrl-C.
    let started = std::time::Instant::now();
    while !partial.exists() {
        assert!(
            started.elapsed().as_secs() < 60,
            "the run never started writing"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let code = child.wait().unwrap().code();
    assert_eq!(code, Some(130));
    assert!(!partial.exists(), "the temporary file was left behind");
    assert!(!csv.exists(), "an interrupted run wrote its output");
    std::fs::remove_dir_all(&dir).ok();
}

/// The last step's rows of a trajectory CSV, without the time column.
fn last_rows(csv: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    let last_t = rows.last().unwrap().split(',').next().unwrap();
    rows.iter()
        .filter(|r| r.split(',').next() == Some(last_t))
        .map(|r| r.split_once(',').unwrap().1.to_string())
        .collect()
}

#[test]
fn a_run_saved_at_a_step_and_restored_ends_bit_for_bit_where_the_whole_run_ends() {
    let dir = std::env::temp_dir().join(format!("kea-cli-snap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = |name: &str| dir.join(name).to_str().unwrap().to_string();
    for (file, form) in [("ragdoll.json", "snap.bin"), ("car.json", "snap.json")] {
        let (code, out, err) = kea(&[
            "run",
            &scene(file),
            "--steps",
            "120",
            "--csv",
            &p("whole.csv"),
        ]);
        assert_eq!(code, 0, "{out}{err}");
        let (code, out, err) = kea(&[
            "run",
            &scene(file),
            "--steps",
            "70",
            "--save-at",
            "50",
            &p(form),
        ]);
        assert_eq!(code, 0, "{out}{err}");
        let (code, out, err) = kea(&[
            "run",
            "--restore",
            &p(form),
            "--steps",
            "70",
            "--csv",
            &p("rest.csv"),
        ]);
        assert_eq!(code, 0, "{out}{err}");
        assert_eq!(
            last_rows(&dir.join("rest.csv")),
            last_rows(&dir.join("whole.csv")),
            "{file} through {form}"
        );
    }
    // Bad uses are refused by name.
    let (code, _, err) = kea(&["run", "--restore", &p("whole.csv")]);
    assert_eq!(code, 1);
    assert!(
        err.contains("--restore") && err.contains("snapshot"),
        "{err}"
    );
    let (code, _, err) = kea(&["run", "--steps", "10", "--save-at", "20", &p("x.bin")]);
    assert_eq!(code, 1);
    assert!(err.contains("--save-at 20"), "{err}");
    let (code, _, err) = kea(&["run", "--save-at", "ten", &p("x.bin")]);
    assert_eq!(code, 1);
    assert!(err.contains("STEP"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_scene_with_a_urdf_robot_runs_and_renders_and_a_missing_robot_file_is_named() {
    let arm = scene("robots/arm.json");
    let (code, out, err) = kea(&["run", &arm, "--steps", "60"]);
    assert_eq!(code, 0, "{err}");
    // The arm's 4 moving bodies (turret, upper arm, forearm with its hand) and the crate.
    assert!(out.contains("4 awake"), "{out}");
    let dir = std::env::temp_dir().join(format!("kea-cli-robot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("arm.png");
    let (code, _, err) = kea(&[
        "render",
        &arm,
        "--out",
        png.to_str().unwrap(),
        "--steps",
        "30",
        "--width",
        "64",
        "--height",
        "48",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(&std::fs::read(&png).unwrap()[..8], b"\x89PNG\r\n\x1a\n");
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"version": 1, "robots": [{"urdf": "missing.urdf"}]}"#,
    )
    .unwrap();
    let (code, _, err) = kea(&["run", bad.to_str().unwrap(), "--steps", "1"]);
    assert_eq!(code, 1);
    assert!(err.contains("missing.urdf"), "{err}");
    std::fs::remove_dir_all(dir).ok();
}
