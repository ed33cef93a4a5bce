//! A progress bar on the terminal while a frame submitted in parts runs
//! (the ground truth of a large scene: `vk::FrameRing`'s parts). Nothing is
//! drawn when stderr is not a terminal, so logs and pipes stay clean.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

use crate::vk::{Progress, ProgressSink};

/// A sink that shows the parts of a frame finish, on stderr; `None` when
/// stderr is not a terminal.
pub fn parts_bar() -> Option<ProgressSink> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let mut bar: Option<ProgressBar> = None;
    Some(Box::new(move |p: &Progress<'_>| {
        let b = bar.get_or_insert_with(|| new_bar(p.total));
        b.set_length(u64::from(p.total));
        b.set_position(u64::from(p.done));
        b.set_message(p.label.to_string());
        if p.done >= p.total {
            b.finish_and_clear();
            bar = None;
        }
    }))
}

fn new_bar(total: u32) -> ProgressBar {
    let bar = ProgressBar::new(u64::from(total));
    // The template is fixed; a bad one would only lose the style.
    if let Ok(style) = ProgressStyle::with_template(
        "{spinner} {msg}: part {pos}/{len} [{bar:30}] {elapsed}, ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    // Ticks while a part runs, so a long part shows it is alive.
    bar.enable_steady_tick(Duration::from_millis(250));
    bar
}
