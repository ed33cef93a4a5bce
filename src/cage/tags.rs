//! OpenSubdiv's `t` tag lines in OBJ cages:
//!
//! ```text
//! t crease 2/1/0 V0 V1 SHARPNESS          edge (V0, V1); more pairs may follow
//! t corner 1/1/0 V SHARPNESS              vertex V; more vertices may follow
//! t interpolateboundary 1/0/0 N           0 none, 1 edge-and-corner, 2 edge-only
//! t hole 2/0/0 F0 F1                      faces F0, F1 give no surface
//! t creasemethod 0/0/1 chaikin            or `normal` (uniform, the default)
//! t smoothtriangles 0/0/1 smooth          or `catmark` (the default)
//! ```
//!
//! `I/F/S` counts the integer, float and string arguments that follow, in
//! that order. Vertex indices are 0-based positions in the file's `v` list
//! (OpenSubdiv's convention, unlike `f` lines). A crease tag lists pairs,
//! each pair an edge: `t crease 4/1/0 a b c d s` sharpens (a, b) and (c, d);
//! its floats are one sharpness for all pairs or one per pair; `corner`
//! likewise per vertex. Sharpness 10 or more is infinitely sharp (`inf` is
//! accepted); a later tag on the same edge or vertex replaces an earlier one.
//!
//! Hole faces are 0-based positions in the file's `f` lines; the faces give
//! no patch, and their neighbours are drawn as if they were there
//! (OpenSubdiv keeps the hole's vertices and edges in the subdivision).
//!
//! Refused, with the line: counts that do not match the arguments, an index
//! that is not a vertex (or, for `hole`, a face), a NaN or negative
//! sharpness, a crease pair that is not an edge of any face, an unknown
//! `interpolateboundary`, `creasemethod` or `smoothtriangles` value, two
//! such tags that disagree. Tags that change nothing OpenSubdiv 3 draws from
//! a cage's positions are named in one warning and ignored: the face-varying
//! ones (`facevaryinginterpolateboundary`, `facevaryingpropagatecorners`:
//! no texture coordinates are read) and hierarchical edits (`vertexedit`,
//! `edgeedit`, `faceedit`: OpenSubdiv 3's refiner has none either); so are
//! unknown tags.

use std::collections::BTreeMap;

use super::sharpness::BoundaryRule;

/// The tags of one file, vertex indices 0-based into its `v` lines.
#[derive(Clone, Debug, Default)]
pub struct Tags {
    /// (line, a, b, sharpness) per crease pair.
    pub creases: Vec<(usize, usize, usize, f64)>,
    /// (line, vertex, sharpness) per corner.
    pub corners: Vec<(usize, usize, f64)>,
    /// The boundary rule and its line.
    pub boundary: Option<(usize, BoundaryRule)>,
    /// (line, face) per hole face, faces 0-based in `f` order.
    pub holes: Vec<(usize, usize)>,
    /// Chaikin creasing (`true`) or uniform, and its line.
    pub chaikin: Option<(usize, bool)>,
    /// OpenSubdiv's smooth triangle rule (`true`) or Catmull–Clark's, and
    /// its line.
    pub smooth_triangles: Option<(usize, bool)>,
    /// Ignored tag names → (count, first line).
    pub ignored: BTreeMap<String, (usize, usize)>,
}

impl Tags {
    /// Reads the words after `t` on line `line`; `vertices` is the number
    /// of `v` lines in the file. The error is the message for that line.
    pub fn read(&mut self, line: usize, words: &[&str], vertices: usize) -> Result<(), String> {
        let tag = TagLine::parse(words, vertices)?;
        match tag.name {
            "crease" => self.read_crease(line, &tag),
            "corner" => self.read_corner(line, &tag),
            "interpolateboundary" => self.read_boundary(line, &tag),
            "hole" => self.read_hole(line, &tag),
            "creasemethod" | "smoothtriangles" => self.read_choice(line, &tag),
            name => {
                let entry = self.ignored.entry(name.to_string()).or_insert((0, line));
                entry.0 += 1;
                Ok(())
            }
        }
    }

    /// `t crease`: pairs of vertices, each an edge, and their sharpness.
    fn read_crease(&mut self, line: usize, tag: &TagLine) -> Result<(), String> {
        let (ni, ns) = (tag.ni, tag.ns);
        if ni < 2 || ni % 2 != 0 || ns != 0 {
            return Err("`t crease` needs pairs of vertices (2, 4, … integers), one or more sharpness values and no strings".into());
        }
        for k in 0..ni / 2 {
            let (a, b) = (
                tag.vertex(tag.ints[2 * k])?,
                tag.vertex(tag.ints[2 * k + 1])?,
            );
            if a == b {
                return Err(format!("`t crease`: the pair ({a}, {b}) is not an edge"));
            }
            self.creases.push((line, a, b, tag.sharpness(k, ni / 2)?));
        }
        Ok(())
    }

    /// `t corner`: vertices and their sharpness.
    fn read_corner(&mut self, line: usize, tag: &TagLine) -> Result<(), String> {
        let (ni, ns) = (tag.ni, tag.ns);
        if ni < 1 || ns != 0 {
            return Err("`t corner` needs one or more vertices and sharpness values".into());
        }
        for (k, &v) in tag.ints.iter().enumerate() {
            self.corners
                .push((line, tag.vertex(v)?, tag.sharpness(k, ni)?));
        }
        Ok(())
    }

    /// `t interpolateboundary`: the boundary rule, the same on every such
    /// line.
    fn read_boundary(&mut self, line: usize, tag: &TagLine) -> Result<(), String> {
        let ints = &tag.ints;
        if (tag.ni, tag.nf, tag.ns) != (1, 0, 0) {
            return Err("`t interpolateboundary` takes one integer (1/0/0)".into());
        }
        let rule = BoundaryRule::from_tag(ints[0]).ok_or_else(|| {
            format!(
                "`t interpolateboundary {}`: expected 0 (none), 1 (edge-and-corner) or 2 (edge-only)",
                ints[0]
            )
        })?;
        if let Some((first, other)) = self.boundary {
            if other != rule {
                return Err(format!(
                    "`t interpolateboundary` says {rule} here but {other} at line {first}"
                ));
            }
        }
        self.boundary = Some((line, rule));
        Ok(())
    }

    /// `t hole`: faces that give no surface.
    fn read_hole(&mut self, line: usize, tag: &TagLine) -> Result<(), String> {
        if tag.ni < 1 || tag.nf != 0 || tag.ns != 0 {
            return Err("`t hole` takes one or more face indices (N/0/0)".into());
        }
        for &f in &tag.ints {
            if f < 0 {
                return Err(format!(
                    "`t hole`: face {f} out of range: faces count from 0"
                ));
            }
            self.holes.push((line, f as usize));
        }
        Ok(())
    }

    /// `t creasemethod` or `t smoothtriangles`: one of two words, the same
    /// on every such line.
    fn read_choice(&mut self, line: usize, tag: &TagLine) -> Result<(), String> {
        let name = tag.name;
        if (tag.ni, tag.nf, tag.ns) != (0, 0, 1) {
            return Err(format!("`t {name}` takes one string (0/0/1)"));
        }
        let word = tag.args[0];
        let (value, choices) = if name == "creasemethod" {
            (
                match word {
                    "normal" => Some(false),
                    "chaikin" => Some(true),
                    _ => None,
                },
                "normal or chaikin",
            )
        } else {
            (
                match word {
                    "catmark" => Some(false),
                    "smooth" => Some(true),
                    _ => None,
                },
                "catmark or smooth",
            )
        };
        let value = value.ok_or_else(|| format!("`t {name} {word}`: expected {choices}"))?;
        let slot = if name == "creasemethod" {
            &mut self.chaikin
        } else {
            &mut self.smooth_triangles
        };
        if let Some((first, other)) = *slot {
            if other != value {
                return Err(format!(
                    "`t {name}` says {word} here but the opposite at line {first}"
                ));
            }
        }
        *slot = Some((line, value));
        Ok(())
    }

    /// One warning naming the ignored tags, if any.
    pub fn ignored_warning(&self) -> Option<String> {
        if self.ignored.is_empty() {
            return None;
        }
        let list: Vec<String> = self
            .ignored
            .iter()
            .map(|(name, (n, line))| format!("`{name}` ×{n} (first at line {line})"))
            .collect();
        let why = |name: &str| match name {
            n if n.starts_with("facevarying") => "no face-varying data is read",
            "vertexedit" | "edgeedit" | "faceedit" => {
                "hierarchical edits, which OpenSubdiv 3 ignores too"
            }
            _ => "unknown",
        };
        let mut reasons: Vec<&str> = self.ignored.keys().map(|n| why(n)).collect();
        reasons.dedup();
        Some(format!(
            "OpenSubdiv tags ignored ({}): {}",
            reasons.join("; "),
            list.join(", ")
        ))
    }
}

/// The words of one `t` line: its name, its argument counts and its
/// arguments, the integers and floats parsed (what every tag checks before
/// its own rules).
struct TagLine<'a> {
    /// The tag's name.
    name: &'a str,
    /// Integer arguments announced.
    ni: usize,
    /// Float arguments announced.
    nf: usize,
    /// String arguments announced.
    ns: usize,
    /// Every argument after the counts.
    args: &'a [&'a str],
    /// The integer arguments.
    ints: Vec<i64>,
    /// The float arguments.
    floats: Vec<f64>,
    /// The number of `v` lines in the file.
    vertices: usize,
}

impl<'a> TagLine<'a> {
    /// Splits the words after `t` into name, counts and arguments, and
    /// parses the integers and floats.
    fn parse(words: &'a [&'a str], vertices: usize) -> Result<Self, String> {
        let Some(&name) = words.first() else {
            return Err("a `t` line needs a tag name".into());
        };
        let counts = words
            .get(1)
            .ok_or_else(|| format!("tag `{name}` needs its argument counts (e.g. 2/1/0)"))?;
        let parsed: Vec<Option<usize>> = counts.split('/').map(|c| c.parse().ok()).collect();
        let [Some(ni), Some(nf), Some(ns)] = parsed[..] else {
            return Err(format!(
                "tag `{name}`: argument counts must be INTS/FLOATS/STRINGS, found {counts:?}"
            ));
        };
        let args = &words[2..];
        if args.len() != ni + nf + ns {
            return Err(format!(
                "tag `{name}` announces {ni}/{nf}/{ns} arguments ({} in all) but has {}",
                ni + nf + ns,
                args.len()
            ));
        }
        let ints = args[..ni]
            .iter()
            .map(|w| {
                w.parse::<i64>()
                    .map_err(|_| format!("tag `{name}`: {w:?} is not an integer"))
            })
            .collect::<Result<Vec<i64>, String>>()?;
        let floats = args[ni..ni + nf]
            .iter()
            .map(|w| {
                w.parse::<f64>()
                    .map_err(|_| format!("tag `{name}`: {w:?} is not a number"))
            })
            .collect::<Result<Vec<f64>, String>>()?;
        Ok(TagLine {
            name,
            ni,
            nf,
            ns,
            args,
            ints,
            floats,
            vertices,
        })
    }

    /// Vertex `i` as an index into the file's `v` lines, or the error.
    fn vertex(&self, i: i64) -> Result<usize, String> {
        let (name, vertices) = (self.name, self.vertices);
        if i < 0 || i as u64 >= vertices as u64 {
            Err(format!(
                "tag `{name}`: vertex {i} out of range: tag vertices count from 0 and the file has {vertices} {}",
                if vertices == 1 { "vertex" } else { "vertices" }
            ))
        } else {
            Ok(i as usize)
        }
    }

    /// The sharpness of item `k` of `items`: the one value for all, or the
    /// item's own.
    fn sharpness(&self, k: usize, items: usize) -> Result<f64, String> {
        let (name, floats) = (self.name, &self.floats);
        let s = match floats.len() {
            1 => floats[0],
            n if n == items => floats[k],
            n => {
                return Err(format!(
                "tag `{name}`: {n} sharpness values for {items} items: give one, or one per item"
            ))
            }
        };
        if s.is_nan() || s < 0.0 {
            return Err(format!("tag `{name}`: sharpness {s} must be a number ≥ 0"));
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(line: &str) -> Result<Tags, String> {
        let mut t = Tags::default();
        let words: Vec<&str> = line.split_whitespace().collect();
        t.read(7, &words, 10).map(|()| t)
    }

    #[test]
    fn reads_the_three_tags() {
        let t = read("crease 4/1/0 1 2 3 4 6.5").unwrap();
        assert_eq!(t.creases, vec![(7, 1, 2, 6.5), (7, 3, 4, 6.5)]);
        let t = read("crease 4/2/0 1 2 3 4 1 inf").unwrap();
        assert_eq!(t.creases[1].3, f64::INFINITY);
        let t = read("corner 2/1/0 0 9 10").unwrap();
        assert_eq!(t.corners, vec![(7, 0, 10.0), (7, 9, 10.0)]);
        let t = read("interpolateboundary 1/0/0 2").unwrap();
        assert_eq!(t.boundary, Some((7, BoundaryRule::EdgeOnly)));
        let t = read("creasemethod 0/0/1 chaikin").unwrap();
        assert_eq!(t.chaikin, Some((7, true)));
        assert!(t.ignored_warning().is_none());
        let t = read("smoothtriangles 0/0/1 smooth").unwrap();
        assert_eq!(t.smooth_triangles, Some((7, true)));
        let t = read("hole 2/0/0 3 0").unwrap();
        assert_eq!(t.holes, vec![(7, 3), (7, 0)]);
        let t = read("vertexedit 1/0/1 3 add").unwrap();
        let w = t.ignored_warning().unwrap();
        assert!(w.contains("`vertexedit` ×1 (first at line 7)"), "{w}");
        assert!(w.contains("OpenSubdiv 3 ignores"), "{w}");
    }

    #[test]
    fn refuses_what_cannot_be_meant() {
        for (line, needle) in [
            ("crease 2/1/0 1 2", "has 2"),
            ("crease 2/1/0 1 x 3", "not an integer"),
            ("crease 3/1/0 1 2 3 4", "pairs"),
            ("crease 2/1/0 1 10 3", "vertex 10 out of range"),
            ("crease 2/1/0 -1 2 3", "out of range"),
            ("crease 2/1/0 1 2 NaN", "≥ 0"),
            ("crease 2/1/0 1 2 -1", "≥ 0"),
            ("crease 4/3/0 1 2 3 4 1 2 3", "3 sharpness values for 2"),
            ("crease 2/1/0 4 4 1", "not an edge"),
            ("corner 1/0/0 3", "sharpness"),
            ("interpolateboundary 1/0/0 3", "expected 0 (none)"),
            ("interpolateboundary x/0/0 3", "INTS/FLOATS/STRINGS"),
            ("hole 1/0/0 -1", "faces count from 0"),
            ("hole 0/0/0", "one or more face"),
            ("creasemethod 0/0/1 sharp", "normal or chaikin"),
            ("smoothtriangles 1/0/0 1", "one string"),
            ("crease", "argument counts"),
        ] {
            let e = read(line).unwrap_err();
            assert!(e.contains(needle), "{line}: {e}");
        }
        let mut t = Tags::default();
        t.read(3, &["interpolateboundary", "1/0/0", "1"], 4)
            .unwrap();
        let e = t
            .read(9, &["interpolateboundary", "1/0/0", "0"], 4)
            .unwrap_err();
        assert!(e.contains("line 3"), "{e}");
    }
}
