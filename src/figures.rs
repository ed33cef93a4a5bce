//! Numbers as the reports write them, and the statistics of repeated
//! frames: leaf helpers that every layer (scene loading, evaluation, the
//! window, the commands) uses, so none of them reaches up into
//! `commands` for them.

/// Formats an integer with thousands separators.
pub fn thousands(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A byte count in the unit that reads best.
pub fn bytes_text(b: u64) -> String {
    let units = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut x = b as f64;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < units.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{b} bytes")
    } else {
        format!("{x:.1} {}", units[u])
    }
}

/// The median of sorted values (the mean of the middle two for an even
/// count; NaN for none).
pub fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

/// GPU time per scope over repeated frames: median, min, max (ms), in the
/// order the scopes were first seen.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timing {
    /// (scope, median, min, max).
    pub scopes: Vec<(String, f64, f64, f64)>,
    /// Frames timed.
    pub frames: usize,
}

impl Timing {
    /// Summarises the per-frame scope times of `frames`.
    pub fn of(frames: &[Vec<(String, f64)>]) -> Self {
        let mut names: Vec<String> = Vec::new();
        for f in frames {
            for (n, _) in f {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
        }
        let scopes = names
            .into_iter()
            .map(|n| {
                let mut v: Vec<f64> = frames
                    .iter()
                    .filter_map(|f| f.iter().find(|(m, _)| *m == n).map(|(_, ms)| *ms))
                    .collect();
                v.sort_by(f64::total_cmp);
                let (lo, hi) = (v[0], v[v.len() - 1]);
                (n, median(&v), lo, hi)
            })
            .collect();
        Timing {
            scopes,
            frames: frames.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousands_groups_digits() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(35940), "35,940");
        assert_eq!(thousands(1234567), "1,234,567");
    }

    #[test]
    fn bytes_read_in_their_unit() {
        assert_eq!(bytes_text(1000), "1000 bytes");
        assert_eq!(bytes_text(1536), "1.5 KiB");
        assert_eq!(bytes_text(64 << 20), "64.0 MiB");
    }

    #[test]
    fn medians_of_known_lists() {
        assert_eq!(median(&[1.0, 2.0, 9.0]), 2.0);
        assert_eq!(median(&[1.0, 2.0, 4.0, 9.0]), 3.0);
        assert!(median(&[]).is_nan());
        let t = Timing::of(&[
            vec![("frame".into(), 3.0), ("draw".into(), 1.0)],
            vec![("frame".into(), 1.0), ("draw".into(), 2.0)],
            vec![("frame".into(), 2.0)],
        ]);
        assert_eq!(t.frames, 3);
        assert_eq!(t.scopes[0], ("frame".to_string(), 2.0, 1.0, 3.0));
        assert_eq!(t.scopes[1], ("draw".to_string(), 1.5, 1.0, 2.0));
    }
}
