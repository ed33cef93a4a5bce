//! The window's keys as a user presses them: on a virtual display (Xvfb),
//! `xdotool` clicks the overlay's buttons and presses the keys, and the
//! screenshots' stats files say what the window did (`overlay_shown`,
//! `path_playing`, the camera, the shading).
//!
//! egui takes Tab for moving its focus and swallows every key while a
//! widget has it (a button clicked last); before the window took its own
//! keys first, Tab never hid the overlay and F12, R, P and Escape did
//! nothing after a click on the overlay. The FLIP button wrote its heat map
//! under `out/` whatever `--screenshot` said.
//!
//! The clicks go to fixed places of the overlay at 1280×720 (egui's own
//! font, 1 pixel per point under Xvfb): the FLIP button and the
//! "wireframe" view. A change of the panel's layout moves them; the test
//! then fails saying which click found nothing.
//!
//! Needs `Xvfb` and `xdotool` (tools/install-deps.sh installs both).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Where the FLIP button, the "wireframe" radio button and the ε value
/// field are.
const FLIP_BUTTON: (u32, u32) = (193, 320);
const WIREFRAME_RADIO: (u32, u32) = (93, 227);
const EPS_FIELD: (u32, u32) = (146, 113);
/// Long enough for lavapipe's first frames on a busy 2-core machine (the
/// first compiles every shader).
const PATIENCE: Duration = Duration::from_secs(300);

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_bezier-subdiv")
}

fn on_path(tool: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(tool).is_file()))
}

/// A child process killed when dropped (the Xvfb server, the window).
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// An Xvfb server on a display number no other server holds.
fn virtual_display() -> (Killed, String) {
    for n in (0..200).map(|k| 100 + (std::process::id() + k) % 800) {
        if Path::new(&format!("/tmp/.X{n}-lock")).exists() {
            continue;
        }
        let display = format!(":{n}");
        let server = Command::new("Xvfb")
            .args([&display, "-screen", "0", "1280x720x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb (tools/install-deps.sh installs it)");
        let mut server = Killed(server);
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(20) {
            if xdotool(&display, &["getdisplaygeometry"]).is_some() {
                return (server, display);
            }
            if server.0.try_wait().ok().flatten().is_some() {
                break; // lost the race for the number
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }
    panic!("no free X display number for Xvfb");
}

/// Runs xdotool on `display`; its output when it succeeded.
fn xdotool(display: &str, args: &[&str]) -> Option<String> {
    let out = Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).to_string())
}

fn wait_for(what: &str, mut done: impl FnMut() -> bool) {
    let start = Instant::now();
    while !done() {
        assert!(
            start.elapsed() < PATIENCE,
            "{what}: nothing after {PATIENCE:?}"
        );
        std::thread::sleep(Duration::from_millis(250));
    }
}

struct Window<'a> {
    display: &'a str,
    shot: PathBuf,
}

impl Window<'_> {
    fn key(&self, key: &str) {
        xdotool(self.display, &["key", key]).expect("xdotool key");
    }

    fn click(&self, (x, y): (u32, u32)) {
        let (x, y) = (x.to_string(), y.to_string());
        xdotool(self.display, &["mousemove", &x, &y, "click", "1"]).expect("xdotool click");
    }

    /// F12 (after `keys`), and the stats file of the screenshot it saved.
    fn screenshot_after(&self, what: &str, keys: &[&str]) -> serde_json::Value {
        let json = self.shot.with_extension("json");
        let _ = std::fs::remove_file(&json);
        for k in keys {
            self.key(k);
        }
        self.key("F12");
        wait_for(&format!("{what}: F12 saved no screenshot"), || {
            std::fs::read(&json)
                .ok()
                .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
                .is_some()
        });
        serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap()
    }

    /// `keys` once, then screenshots until one's stats satisfy `done`: a
    /// screenshot saves the last frame drawn, which a key pressed in the
    /// same frame has not changed yet. Fails saying `what` when none does.
    fn screenshot_until(
        &self,
        what: &str,
        keys: &[&str],
        done: impl Fn(&serde_json::Value) -> bool,
    ) -> serde_json::Value {
        let start = Instant::now();
        let mut stats = self.screenshot_after(what, keys);
        while !done(&stats) {
            assert!(start.elapsed() < PATIENCE, "{what}: {stats}");
            stats = self.screenshot_after(what, &[]);
        }
        stats
    }
}

#[test]
fn the_window_keys_work_after_clicks_and_tab() {
    assert!(
        on_path("Xvfb") && on_path("xdotool"),
        "Xvfb and xdotool are needed: run tools/install-deps.sh"
    );
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("view-keys-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A working directory of its own: nothing may land in its out/.
    let cwd = dir.join("cwd");
    std::fs::create_dir_all(&cwd).unwrap();
    let (_server, display) = virtual_display();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml");
    let w = Window {
        display: &display,
        shot: dir.join("shot.png"),
    };
    // To a file: a pipe nobody reads while the window runs could fill.
    let log = dir.join("view.log");
    let mut view = Killed(
        Command::new(bin())
            .args(["view", "--vk-validation", "--scene"])
            .arg(&scene)
            .arg("--screenshot")
            .arg(&w.shot)
            .current_dir(&cwd)
            .env("DISPLAY", &display)
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .unwrap(),
    );
    let id = xdotool(&display, &["search", "--sync", "--name", "^bezier-subdiv"])
        .expect("the window never appeared");
    let id = id.lines().next().unwrap().to_string();
    // Without a window manager the keyboard focus is set by hand.
    xdotool(&display, &["windowfocus", "--sync", &id]).expect("focus the window");

    // Frames are running (the overlay is laid out): F12 saves one.
    let start = w.screenshot_after("the first frames", &[]);
    assert_eq!(start["overlay_shown"], true);
    assert_eq!(start["path_playing"], false);
    assert_eq!(start["shade"], "normal");

    // The FLIP button writes beside --screenshot, not into out/.
    w.click(FLIP_BUTTON);
    let heat = dir.join("shot-flip-1.png");
    wait_for(
        &format!(
            "the FLIP button at {FLIP_BUTTON:?} wrote no {}",
            heat.display()
        ),
        || heat.is_file(),
    );
    assert!(!cwd.join("out").exists(), "the FLIP button wrote into out/");

    // The button has egui's focus now: Tab still hides the overlay and
    // F12 still saves.
    w.screenshot_until(
        "Tab after a click did not hide the overlay",
        &["Tab"],
        |s| s["overlay_shown"] == false,
    );

    // Tab shows it again; P plays the camera path.
    w.screenshot_until("Tab, P: no path played", &["Tab", "p"], |s| {
        s["overlay_shown"] == true && s["path_playing"] == true
    });

    // A click on a view button (it takes the focus; the overlay applies it
    // when it is next laid out), then R: back to the scene camera, the path
    // stopped.
    w.click(WIREFRAME_RADIO);
    let clicked = format!("the click at {WIREFRAME_RADIO:?} missed the wireframe button");
    w.screenshot_until(&clicked, &[], |s| s["shade"] == "wireframe");
    w.screenshot_until("R did not reset the camera", &["r"], |s| {
        s["path_playing"] == false && s["camera"] == start["camera"]
    });

    // A value field being typed in (a click on ε's number edits it): F12
    // still saves (it once did nothing), Escape leaves the field instead
    // of closing the window, and then F12 saves again.
    w.click(EPS_FIELD);
    w.screenshot_after("F12 while typing in the ε field", &[]);
    w.key("Escape");
    std::thread::sleep(Duration::from_millis(500));
    assert!(
        view.0.try_wait().unwrap().is_none(),
        "Escape in a value field closed the window"
    );
    w.screenshot_after("F12 after leaving the field", &[]);

    // Escape closes the window, the focus still on the button.
    w.key("Escape");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = view.0.try_wait().unwrap() {
            break status;
        }
        assert!(
            start.elapsed() < PATIENCE,
            "Escape did not close the window"
        );
        std::thread::sleep(Duration::from_millis(250));
    };
    let err = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(status.success(), "view failed: {err}");
    let _ = std::fs::remove_dir_all(&dir);
}
