//! Reading a deck's text: `*INCLUDE` files expanded in place (with the
//! map back to each file's lines) and each line lexed into keyword and data
//! items.

use super::*;

/// Deepest chain of `*INCLUDE`s followed.
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// Largest expanded deck in bytes (1 GiB): a deck that includes the same
/// file many times over at several levels grows exponentially.
pub const MAX_EXPANDED_BYTES: usize = 1 << 30;

/// A deck with its `*INCLUDE` lines replaced by the included files' text,
/// and for every line of that text the file and line it came from.
#[derive(Debug, Clone)]
pub struct ExpandedDeck {
    /// The text, includes in place.
    pub text: String,
    /// The files read: the deck first, then each included file once.
    pub files: Vec<String>,
    /// `(file index, 1-based line)` of each line of `text`.
    origin: Vec<(u32, u32)>,
}

impl ExpandedDeck {
    /// `err` (located in `text`, named after `files[0]`) with the file and
    /// line of the deck or included file the line came from.
    pub fn relocate(&self, mut err: InpError) -> InpError {
        use InpError::*;
        let loc = match &mut err {
            Io { .. } => None,
            UnknownKeyword { file, line, .. }
            | Parameter { file, line, .. }
            | MissingParameter { file, line, .. }
            | ElementType { file, line, .. }
            | BadNumber { file, line, .. }
            | UndefinedLabel { file, line, .. }
            | UnknownName { file, line, .. }
            | Invalid { file, line, .. } => Some((file, line)),
        };
        if let Some((file, line)) = loc {
            if let Some(&(f, l)) = line.checked_sub(1).and_then(|i| self.origin.get(i)) {
                *file = self.files[f as usize].clone();
                *line = l as usize;
            }
        }
        err
    }
}

/// The `INPUT=` file of an `*INCLUDE` keyword line (`None` if `line` is
/// not one; `Some(Err(..))` without an `INPUT`).
pub(super) fn include_target(line: &str) -> Option<Result<String, ()>> {
    let rest = line.trim().strip_prefix('*')?;
    let mut parts = rest.split(',');
    if norm_key(parts.next()?) != "INCLUDE" {
        return None;
    }
    for p in parts {
        if let Some((k, v)) = p.split_once('=') {
            if norm_key(k) == "INPUT" {
                let v = v.trim().trim_matches('"').trim_matches('\'').trim();
                return Some(if v.is_empty() {
                    Err(())
                } else {
                    Ok(v.to_string())
                });
            }
        }
    }
    Some(Err(()))
}

/// Read `path` and, recursively, every file an `*INCLUDE, INPUT=name`
/// line names (CalculiX and Abaqus), in place of that line. A relative
/// name is looked for next to the file that includes it, then in the
/// working directory. Errors, naming the including file and line: a
/// missing `INPUT`, a file that cannot be read, an include cycle, more
/// than [`MAX_INCLUDE_DEPTH`] levels, or an expanded deck over
/// [`MAX_EXPANDED_BYTES`].
pub fn expand_includes(path: &Path) -> Result<ExpandedDeck, InpError> {
    let mut out = ExpandedDeck {
        text: String::new(),
        files: Vec::new(),
        origin: Vec::new(),
    };
    let text = std::fs::read_to_string(path).map_err(|source| InpError::Io {
        file: path.display().to_string(),
        source,
    })?;
    let mut stack = Vec::new();
    expand_into(path, text, &mut out, &mut stack)?;
    Ok(out)
}

pub(super) fn expand_into(
    path: &Path,
    text: String,
    out: &mut ExpandedDeck,
    stack: &mut Vec<std::path::PathBuf>,
) -> Result<(), InpError> {
    let name = path.display().to_string();
    let fi = match out.files.iter().position(|f| *f == name) {
        Some(i) => i,
        None => {
            out.files.push(name.clone());
            out.files.len() - 1
        }
    };
    stack.push(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()));
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let invalid = |line: usize, message: String| InpError::Invalid {
        file: name.clone(),
        line,
        keyword: "INCLUDE".into(),
        message,
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        match include_target(raw) {
            None => {
                if out.text.len() + raw.len() + 1 > MAX_EXPANDED_BYTES {
                    return Err(invalid(
                        line,
                        format!(
                            "the deck with its included files exceeds {} MiB",
                            MAX_EXPANDED_BYTES >> 20
                        ),
                    ));
                }
                out.text.push_str(raw);
                out.text.push('\n');
                out.origin.push((fi as u32, line as u32));
            }
            Some(Err(())) => {
                return Err(invalid(line, "needs INPUT=<file name>".into()));
            }
            Some(Ok(target)) => {
                let beside = dir.join(&target);
                let found = if beside.exists() {
                    beside
                } else {
                    std::path::PathBuf::from(&target)
                };
                let canon = std::fs::canonicalize(&found).unwrap_or_else(|_| found.clone());
                if stack.contains(&canon) {
                    return Err(invalid(
                        line,
                        format!(
                            "INPUT={target} includes itself (through {} level(s))",
                            stack.len()
                        ),
                    ));
                }
                if stack.len() >= MAX_INCLUDE_DEPTH {
                    return Err(invalid(
                        line,
                        format!(
                            "INPUT={target}: more than {MAX_INCLUDE_DEPTH} nested *INCLUDE levels"
                        ),
                    ));
                }
                let inner = std::fs::read_to_string(&found).map_err(|e| {
                    invalid(
                        line,
                        format!(
                            "cannot read INPUT={target} (looked for {}): {e}",
                            dir.join(&target).display()
                        ),
                    )
                })?;
                expand_into(&found, inner, out, stack)?;
            }
        }
    }
    stack.pop();
    Ok(())
}

#[derive(Debug)]
pub(super) enum Item<'a> {
    Keyword {
        line: usize,
        name: String,
        params: Vec<(String, Option<String>)>,
    },
    Data {
        line: usize,
        raw: &'a str,
        fields: Vec<&'a str>,
        continues: bool,
    },
}

/// One line of a deck, lexed alone.
pub(super) enum Line<'a> {
    /// Blank or a `**` comment.
    Skip,
    /// A keyword line: its text after the `*`.
    Keyword(&'a str),
    /// A data line.
    Data(Item<'a>),
}

/// The deck's items: each line is lexed alone (in parallel: a large deck's
/// data lines are most of the reading time), then keyword lines ending with
/// a comma take the data lines that follow them as their continuation.
pub(super) fn lex(text: &str) -> Vec<Item<'_>> {
    let lines: Vec<&str> = text.lines().collect();
    let lexed: Vec<Line<'_>> = lines
        .par_iter()
        .enumerate()
        .map(|(i, raw)| lex_line(i + 1, raw))
        .collect();
    let mut items = Vec::with_capacity(lexed.len());
    let mut lexed = lexed.into_iter().enumerate().peekable();
    while let Some((i, line)) = lexed.next() {
        match line {
            Line::Skip => {}
            Line::Data(item) => items.push(item),
            Line::Keyword(rest) => {
                let mut full = rest.to_string();
                // keyword-line continuation
                while full.trim_end().ends_with(',') {
                    match lexed.peek() {
                        Some((_, Line::Data(Item::Data { raw, .. }))) => {
                            full.push_str(raw);
                            lexed.next();
                        }
                        _ => break,
                    }
                }
                items.push(keyword_item(i + 1, &full));
            }
        }
    }
    items
}

/// Line `line` (1-based) of a deck, alone.
pub(super) fn lex_line(line: usize, raw: &str) -> Line<'_> {
    let l = raw.trim();
    if l.is_empty() || l.starts_with("**") {
        return Line::Skip;
    }
    if let Some(rest) = l.strip_prefix('*') {
        return Line::Keyword(rest);
    }
    let continues = l.ends_with(',');
    let mut fields: Vec<&str> = l.split(',').map(str::trim).collect();
    if continues {
        fields.pop();
    }
    Line::Data(Item::Data {
        line,
        raw: l,
        fields,
        continues,
    })
}

/// A keyword line's name (upper case, single spaces) and parameters.
pub(super) fn keyword_item(line: usize, full: &str) -> Item<'static> {
    let mut parts = full.split(',');
    let name = parts
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_uppercase();
    let params = parts
        .filter(|p| !p.trim().is_empty())
        .map(|p| match p.split_once('=') {
            Some((k, v)) => (norm_key(k), Some(v.trim().to_string())),
            None => (norm_key(p), None),
        })
        .collect();
    Item::Keyword { line, name, params }
}

pub(super) fn norm_key(k: &str) -> String {
    k.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_uppercase()
}
