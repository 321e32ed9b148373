//! The binary without a display, and under a virtual X display (Xvfb) with a real screenshot.

use std::collections::HashMap;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_edmd-view");

/// Runs `cmd`, killing it if it takes longer than `limit`.
fn run_with_timeout(cmd: &mut Command, limit: Duration) -> Output {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the command");
    let start = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("collect output");
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().expect("collect output");
            panic!(
                "timed out after {limit:?}; stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn without_a_display_one_line_and_status_2() {
    let out = run_with_timeout(
        Command::new(BIN)
            .args(["--gen", "fluid", "--n", "100"])
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("WAYLAND_SOCKET"),
        Duration::from_secs(60),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "stderr: {stderr}");
    assert!(
        stderr.contains("no display") && stderr.contains("edmd render"),
        "{stderr}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn bad_arguments_are_one_line_and_status_2() {
    let out = run_with_timeout(
        Command::new(BIN)
            .args(["--gen", "nonsense"])
            .env("DISPLAY", ":12345"),
        Duration::from_secs(60),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "stderr: {stderr}");
    assert!(stderr.contains("unknown kind"), "{stderr}");
}

#[test]
fn a_display_that_cannot_be_opened_is_one_line_and_status_2() {
    let out = run_with_timeout(
        Command::new(BIN)
            .args(["--gen", "fluid", "--n", "100"])
            .env("DISPLAY", ":12345")
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("WAYLAND_SOCKET"),
        Duration::from_secs(60),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "stderr: {stderr}");
    assert!(stderr.contains("no display"), "{stderr}");
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
}

/// Reads an 8-bit RGB or RGBA PNG: (width, height, pixels as RGB).
fn read_png(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("unexpected colour type {other:?}"),
    };
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, pixels)
}

#[test]
fn screenshot_under_xvfb() {
    if !on_path("xvfb-run") {
        if std::env::var_os("CI").is_some() {
            panic!("xvfb-run is not installed, and CI is set: install xvfb and xauth");
        }
        // Past the harness's capture: Rust's tests have no real skip, so this line is the sign.
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED screenshot_under_xvfb: xvfb-run is not installed (apt-get install xvfb xauth)"
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("out.png");
    let out = run_with_timeout(
        Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24", BIN])
            .args([
                "--gen",
                "fluid",
                "--n",
                "500",
                "--fps-report",
                "--quit-after",
                "3",
            ])
            .arg("--screenshot")
            .arg(&shot)
            .env_remove("WAYLAND_DISPLAY"),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "status {:?}; stderr: {stderr}",
        out.status
    );
    assert!(stdout.contains("frames per second"), "stdout: {stdout}");
    assert!(shot.is_file(), "no screenshot; stderr: {stderr}");
    let (w, h, pixels) = read_png(&shot);
    assert!(w >= 600 && h >= 400, "{w} x {h}");
    let mut counts: HashMap<[u8; 3], usize> = HashMap::new();
    for p in &pixels {
        *counts.entry(*p).or_default() += 1;
    }
    // Not blank: many colours (text, plots, antialiased discs), none covering nearly everything.
    assert!(counts.len() > 100, "only {} distinct colours", counts.len());
    let most = counts.values().max().copied().unwrap_or(0);
    assert!(
        (most as f64) < 0.9 * pixels.len() as f64,
        "one colour covers {most} pixels"
    );
    // The picture is there: the box background, and the fluid's discs (black in its file
    // colours), many of them.
    let white = counts.get(&edmd_draw::BACKGROUND).copied().unwrap_or(0);
    let black = counts.get(&[0, 0, 0]).copied().unwrap_or(0);
    assert!(white > 10_000, "box background: {white} pixels");
    assert!(black > 20_000, "disc pixels: {black}");
    // The plot of the Rayleigh law and the histogram bars use their own colours.
    let [r, g, b] = [31u8, 119, 180];
    let bars = pixels
        .iter()
        .filter(|p| {
            (p[0] as i32 - r as i32).abs() < 40
                && (p[1] as i32 - g as i32).abs() < 40
                && (p[2] as i32 - b as i32).abs() < 40
        })
        .count();
    assert!(bars > 100, "histogram bars: {bars} pixels");
}

/// A 3D file opens as shaded spheres: the screenshot holds the outside colour around the box
/// and many shades of the spheres' grey (the shading), with the Maxwell law plotted.
#[test]
fn spheres_under_xvfb() {
    if !on_path("xvfb-run") {
        if std::env::var_os("CI").is_some() {
            panic!("xvfb-run is not installed, and CI is set: install xvfb and xauth");
        }
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED spheres_under_xvfb: xvfb-run is not installed (apt-get install xvfb xauth)"
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("out.png");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/spheres-500.txt");
    let out = run_with_timeout(
        Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24", BIN])
            .arg(&file)
            .args(["--fps-report", "--quit-after", "3", "--screenshot"])
            .arg(&shot)
            .env_remove("WAYLAND_DISPLAY"),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "status {:?}; stderr: {stderr}",
        out.status
    );
    // The summary on exit called spheres discs.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(", 500 spheres;"), "stdout: {stdout}");
    let (_, _, pixels) = read_png(&shot);
    let outside = pixels.iter().filter(|p| **p == edmd_draw::OUTSIDE).count();
    assert!(outside > 20_000, "outside the box: {outside} pixels");
    // The spheres are black in the file: shaded, they show as many distinct greys.
    let greys: std::collections::HashSet<[u8; 3]> = pixels
        .iter()
        .filter(|p| p[0] == p[1] && p[1] == p[2] && p[0] > 5 && p[0] < 200)
        .copied()
        .collect();
    assert!(greys.len() > 60, "{} shades of grey", greys.len());
}

/// A square-well lattice with `--bonds --colour energy`: the screenshot shows the bonds (in
/// their orange) and the bound discs (blue, each with four partners).
#[test]
fn bonds_and_energy_colours_under_xvfb() {
    if !on_path("xvfb-run") {
        if std::env::var_os("CI").is_some() {
            panic!("xvfb-run is not installed, and CI is set: install xvfb and xauth");
        }
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED bonds_and_energy_colours_under_xvfb: xvfb-run is not installed (apt-get install xvfb xauth)"
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("out.png");
    // 20 x 20 discs of diameter 1, 1.25 apart in a periodic box: each pair of neighbours is
    // inside the well (out to 1.5), diagonal ones (1.77 apart) are not. Slow velocities keep
    // the lattice for the few seconds of the test.
    let file = dir.path().join("lattice.txt");
    let mut text =
        "400\n# edmd box 25 25\n# edmd boundary periodic periodic\n# edmd potential 0 0 1.5 -1.0\n"
            .to_string();
    for k in 0..400 {
        let (x, y) = (
            0.625 + 1.25 * (k % 20) as f64,
            0.625 + 1.25 * (k / 20) as f64,
        );
        let (vx, vy) = (0.01 * (k as f64).sin(), 0.01 * (k as f64 * 1.7).cos());
        text += &format!("{x} {y} {vx} {vy} 0.5 1 0 0 0\n");
    }
    std::fs::write(&file, text).unwrap();
    let out = run_with_timeout(
        Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24", BIN])
            .arg(&file)
            .args(["--bonds", "--colour", "energy", "--quit-after", "3"])
            .arg("--screenshot")
            .arg(&shot)
            .env_remove("WAYLAND_DISPLAY"),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "status {:?}; stderr: {stderr}",
        out.status
    );
    let (_, _, pixels) = read_png(&shot);
    let orange = pixels
        .iter()
        .filter(|p| p[0] > 180 && (80..170).contains(&p[1]) && p[2] < 110)
        .count();
    let blue = pixels
        .iter()
        .filter(|p| p[2] as i32 > p[0] as i32 + 60)
        .count();
    assert!(orange > 2_000, "bond pixels: {orange}");
    assert!(blue > 20_000, "bound disc pixels: {blue}");
}

/// A 1D file opens as rods on a line above its phase plane: the strip shows the rods' bars in
/// their file colours (the twelve rods of the guide's example, three of each colour), and the
/// summary counts rods.
#[test]
fn rods_under_xvfb() {
    if !on_path("xvfb-run") {
        if std::env::var_os("CI").is_some() {
            panic!("xvfb-run is not installed, and CI is set: install xvfb and xauth");
        }
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED rods_under_xvfb: xvfb-run is not installed (apt-get install xvfb xauth)"
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("out.png");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data/rods-1d.txt");
    let out = run_with_timeout(
        Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24", BIN])
            .arg(&file)
            .args(["--fps-report", "--quit-after", "3", "--screenshot"])
            .arg(&shot)
            .env_remove("WAYLAND_DISPLAY"),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "status {:?}; stderr: {stderr}",
        out.status
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(", 12 rods;"), "stdout: {stdout}");
    let (_, _, pixels) = read_png(&shot);
    // Each rod is a bar of a twentieth of the line and 24 pixels high.
    for colour in [[220, 60, 40], [40, 90, 200], [240, 170, 20], [40, 160, 80]] {
        let n = pixels.iter().filter(|p| **p == colour).count();
        assert!(n > 1_000, "{colour:?}: {n} pixels");
    }
}
