//! Line-oriented number reading shared by the formats.

use std::fmt;

/// A problem in an input file: the 1-based line and what is wrong there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// 1-based line number (the last line for "file ends too early").
    pub line: usize,
    /// What is wrong, in words.
    pub message: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for ParseError {}

/// Non-blank, non-comment lines with their 1-based numbers. Lines whose first non-blank
/// character is `#` are comments; comments of the form `# edmd WORD ...` are directives and are
/// kept, with their line numbers, in [`Lines::directives`].
pub(crate) struct Lines<'a> {
    inner: std::iter::Enumerate<std::str::Lines<'a>>,
    /// Number of the last line seen (for end-of-file messages).
    pub last: usize,
    /// `(line, words after "# edmd")` of every directive seen so far.
    pub directives: Vec<(usize, Vec<&'a str>)>,
}

impl<'a> Lines<'a> {
    /// A byte order mark at the start (what some Windows editors put before UTF-8 text) is
    /// not part of the first line.
    pub fn new(text: &'a str) -> Self {
        Lines {
            inner: text
                .strip_prefix('\u{feff}')
                .unwrap_or(text)
                .lines()
                .enumerate(),
            last: 0,
            directives: Vec::new(),
        }
    }

    /// The next non-blank, non-comment line as `(number, fields)`.
    pub fn next_fields(&mut self) -> Option<(usize, Vec<&'a str>)> {
        for (k, l) in self.inner.by_ref() {
            self.last = k + 1;
            let f: Vec<&str> = l.split_whitespace().collect();
            if f.is_empty() {
                continue;
            }
            if f[0].starts_with('#') {
                let words: Vec<&str> = l
                    .trim_start()
                    .trim_start_matches('#')
                    .split_whitespace()
                    .collect();
                if words.first() == Some(&"edmd") {
                    self.directives.push((k + 1, words[1..].to_vec()));
                }
                continue;
            }
            return Some((k + 1, f));
        }
        None
    }

    /// Like [`Self::next_fields`], but a missing line is an error saying what was expected.
    pub fn expect_fields(&mut self, what: &str) -> Result<(usize, Vec<&'a str>), ParseError> {
        let last = self.last;
        self.next_fields().ok_or_else(|| ParseError {
            line: last.max(1),
            message: format!("file ends before {what}"),
        })
    }
}

pub(crate) fn err(line: usize, message: impl Into<String>) -> ParseError {
    ParseError {
        line,
        message: message.into(),
    }
}

/// Checks that a line has exactly `names.len()` fields and parses them as finite numbers.
pub(crate) fn numbers(
    line: usize,
    fields: &[&str],
    names: &[&str],
) -> Result<Vec<f64>, ParseError> {
    if fields.len() != names.len() {
        return Err(err(
            line,
            format!(
                "expected {} number{} ({}), found {}",
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                names.join(" "),
                fields.len()
            ),
        ));
    }
    fields
        .iter()
        .zip(names)
        .map(|(f, name)| number(line, f, name))
        .collect()
}

/// One finite number.
pub(crate) fn number(line: usize, field: &str, name: &str) -> Result<f64, ParseError> {
    let x: f64 = field
        .parse()
        .map_err(|_| err(line, format!("{name} is not a number: '{field}'")))?;
    if !x.is_finite() {
        return Err(err(line, format!("{name} is not finite: '{field}'")));
    }
    Ok(x)
}

/// The disc count on a line of its own.
pub(crate) fn count(lines: &mut Lines) -> Result<usize, ParseError> {
    let (line, f) = lines
        .next_fields()
        .ok_or_else(|| err(1, "the file is empty"))?;
    if f.len() != 1 {
        return Err(err(
            line,
            format!(
                "expected the number of discs alone, found {} fields",
                f.len()
            ),
        ));
    }
    f[0].parse::<usize>().map_err(|_| {
        err(
            line,
            format!(
                "the number of discs must be a whole number >= 0, found '{}'",
                f[0]
            ),
        )
    })
}

/// After the last disc: only blank lines may follow.
pub(crate) fn expect_end(lines: &mut Lines, n: usize) -> Result<(), ParseError> {
    match lines.next_fields() {
        Some((line, _)) => Err(err(
            line,
            format!("more disc lines than the {n} announced on the first line"),
        )),
        None => Ok(()),
    }
}

/// Shortest text that reads back as the same `f64`.
pub(crate) fn exact(x: f64) -> String {
    format!("{x:?}")
}
