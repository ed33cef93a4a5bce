//! Reading model and scene files as text.

use super::error::SceneError;

/// Reads a text file. A file that is not UTF-8 text is refused at the line
/// of its first invalid byte (a binary file named `.bpt` or `.obj`).
pub fn read_text(path: &std::path::Path) -> Result<String, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        SceneError::at(
            path,
            line,
            format!("not a text file: byte {at} is not UTF-8 (model files are plain text)"),
        )
    })
}

/// The statements of OBJ text: each line that is not blank as its number
/// (from 1, for errors), its keyword and the words after it.
pub fn statements(text: &str) -> impl Iterator<Item = (usize, &str, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let mut words = line.split_whitespace();
        let keyword = words.next()?;
        Some((i + 1, keyword, words.collect()))
    })
}
