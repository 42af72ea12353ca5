//! Where things are in a scenario's text: the line of an offset, of a field, of a table's key.

/// The 1-based line of byte offset `at`.
pub(crate) fn line_at(source: &str, at: usize) -> usize {
    source[..at.min(source.len())].matches('\n').count() + 1
}

/// Where each line of a source starts, for the lines of many offsets: [`line_at`] counts the
/// newlines before each one, which for a table per disc made a file of `N` discs take
/// `O(N²)`.
pub(crate) struct LineIndex(Vec<usize>);

impl LineIndex {
    pub(crate) fn new(source: &str) -> LineIndex {
        LineIndex(
            source
                .bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(k, _)| k)
                .collect(),
        )
    }

    /// The 1-based line of byte offset `at`, as [`line_at`] gives it.
    pub(crate) fn at(&self, at: usize) -> usize {
        self.0.partition_point(|&newline| newline < at) + 1
    }
}

/// `table.key` for a `key = value` line (1-based), for messages that only know the line.
pub(crate) fn field_at(source: &str, line: usize) -> Option<String> {
    let mut table = String::new();
    for (n, text) in source.lines().enumerate() {
        let t = text.trim();
        if t.starts_with('[') {
            table = t.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        }
        if n + 1 == line {
            let key = t.split('=').next()?.trim();
            if key.is_empty() || key.starts_with('[') || !t.contains('=') {
                return None;
            }
            return Some(if table.is_empty() {
                key.to_string()
            } else {
                format!("{table}.{key}")
            });
        }
    }
    None
}

/// The line of `key = ...` inside `[table]`, for messages about plain fields.
pub(crate) fn line_of_key(source: &str, table: &str, key: &str) -> Option<usize> {
    let mut current = String::new();
    for (n, line) in source.lines().enumerate() {
        let t = line.trim();
        if t.starts_with('[') {
            current = t.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        } else if current == table
            && t.strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        {
            return Some(n + 1);
        }
    }
    None
}
