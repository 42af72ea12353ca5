//! Reading scenario text into *every* problem it has, in line order, the way `bounce check`
//! reports them: the type errors past the first (each offending line is set aside and the
//! text read again), the semantic problems of what remains, a typo's nearest key, and a
//! problem in a `--set` override named by the override rather than a line of the file.

use crate::{Problem, Scenario};

/// The most type errors read from one file before giving up on the rest.
const MAX_TYPE_ERRORS: usize = 100;

/// What [`examine`] found: the scenario as far as it could be read (`None` when a syntax error
/// or a missing key stopped the reading) and every problem, in line order.
pub(crate) struct Examined {
    /// The scenario read from the text with its bad lines set aside.
    pub scenario: Option<Scenario>,
    /// Every problem found, sorted by line (those without a line last).
    pub problems: Vec<Problem>,
}

/// Values tried in place of one of the wrong type, so the reading can go on to the next
/// key: one of them has the type the key wants (an enum's names are tried first, from the
/// error's own list).
const STAND_INS: [&str; 7] = [
    "1",
    "1.0",
    "true",
    "\"A\"",
    "[1.0, 1.0]",
    "[[1.0, 1.0], [2.0, 2.0]]",
    "{ min = [0.0, 0.0], max = [1.0, 1.0] }",
];

/// Reads `source` as a scenario and lists every problem a reading can find. Type errors come
/// one by one: the offending key is given a stand-in of the right type (or, unknown, left
/// out) and the text read again, keeping the line numbers. A file without type errors is then
/// checked for its semantic problems. (With type errors those are left for the next run: a
/// stand-in's value would make problems of its own.)
pub(crate) fn examine(source: &str) -> Examined {
    let mut problems = Vec::new();
    let mut scenario = None;
    let (_, syntax) = toml::de::DeTable::parse_recoverable(source);
    if !syntax.is_empty() {
        // Syntax errors: as many as the parser finds, then no reading of the values.
        problems.extend(syntax.iter().map(|e| located(source, e)));
    } else {
        let mut text = source.to_string();
        for _ in 0..MAX_TYPE_ERRORS {
            match toml::from_str::<Scenario>(&text) {
                Ok(s) if problems.is_empty() => {
                    problems.extend(s.problems(&text));
                    scenario = Some(s);
                    break;
                }
                Ok(_) => break,
                Err(e) => {
                    let problem = located(&text, &e);
                    let next = problem.line.and_then(|line| go_past(&text, line, &e));
                    problems.push(problem);
                    match next {
                        Some(next) => text = next,
                        None => break,
                    }
                }
            }
        }
    }
    for problem in &mut problems {
        attribute_override(source, problem);
    }
    sort(&mut problems);
    Examined { scenario, problems }
}

/// `text` with the key on `line` given a value the reading gets past (an unknown key left
/// out), so that the next error shows; `None` where no such edit is found.
fn go_past(text: &str, line: usize, e: &toml::de::Error) -> Option<String> {
    let current = text.lines().nth(line - 1)?;
    let (key, _) = current.split_once('=')?;
    if current.trim_start().starts_with('[') {
        return None;
    }
    let message = e.message();
    // Past it: the next error is elsewhere, and not this key gone missing.
    let missing = format!("missing field `{}`", key.trim());
    let read_past = |candidate: &str| {
        let edited = replace_line(text, line, candidate);
        match toml::from_str::<Scenario>(&edited) {
            Ok(_) => Some(edited),
            Err(next) => {
                let at = next.span().map(|s| crate::lines::line_at(&edited, s.start));
                let past = at != Some(line) && next.message() != message;
                (past && !next.message().contains(&missing)).then_some(edited)
            }
        }
    };
    if message.starts_with("unknown field") {
        return read_past("");
    }
    let names: Vec<String> = message
        .split_once("expected")
        .map(|(_, list)| {
            list.split('`')
                .skip(1)
                .step_by(2)
                .map(|n| format!("\"{n}\""))
                .collect()
        })
        .unwrap_or_default();
    names
        .iter()
        .map(String::as_str)
        .chain(STAND_INS)
        .map(|value| format!("{} = {value}", key.trim_end()))
        .chain([String::new()])
        .find_map(|candidate| read_past(&candidate))
}

/// `text` with line `line` (1-based) replaced by `with`, the line count kept.
fn replace_line(text: &str, line: usize, with: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for (n, l) in text.split_inclusive('\n').enumerate() {
        if n + 1 == line {
            out.push_str(with);
            if l.ends_with('\n') {
                out.push('\n');
            }
        } else {
            out.push_str(l);
        }
    }
    out
}

/// Problems in line order, those without a line last; the same problem once.
pub(crate) fn sort(problems: &mut Vec<Problem>) {
    problems.sort_by_key(|p| p.line.unwrap_or(usize::MAX));
    let mut seen = std::collections::HashSet::new();
    problems.retain(|p| seen.insert((p.line, p.message.clone())));
}

/// A parse error as a problem at its line, naming the key the line sets, with the nearest
/// known key for an unknown one.
fn located(source: &str, e: &toml::de::Error) -> Problem {
    let message = e.message().trim().replace('\n', " ");
    // A typo's nearest key says more than the list of every key.
    let message = match (nearest_key(&message), message.split_once(", expected")) {
        (Some(near), Some((unknown, _))) => format!("{unknown} (did you mean `{near}`?)"),
        _ => message,
    };
    match e.span() {
        Some(span) => {
            let line = crate::lines::line_at(source, span.start);
            match crate::lines::field_at(source, line) {
                Some(field) if !message.contains(&field) => Problem {
                    line: Some(line),
                    message: format!("`{field}`: {message}"),
                },
                _ => Problem {
                    line: Some(line),
                    message,
                },
            }
        }
        None => Problem {
            line: None,
            message,
        },
    }
}

/// For "unknown field `gravty`, expected one of `gravity`, ...": the expected key nearest the
/// unknown one, if it is near enough to be a typo.
fn nearest_key(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    let (unknown, rest) = rest.split_once('`')?;
    let (_, expected) = rest.split_once("expected")?;
    let known = expected.split('`').skip(1).step_by(2);
    let (distance, near) = known
        .map(|k| (strsim::damerau_levenshtein(unknown, k), k))
        .min()?;
    (distance <= (unknown.chars().count() / 3).max(2)).then(|| near.to_string())
}

/// A problem on a line a `--set` override wrote (marked `# --set KEY=VALUE` by
/// [`crate::overrides::apply`]) names the override instead of the line.
fn attribute_override(source: &str, problem: &mut Problem) {
    let Some(line) = problem.line else { return };
    let Some(text) = source.lines().nth(line - 1) else {
        return;
    };
    if let Some((_, set)) = text.split_once(crate::overrides::MARK) {
        let set = set.trim();
        // The override names the key and its value: a message's own naming of them goes.
        let key = set.split('=').next().unwrap_or(set).trim();
        let message = match problem.message.split_once(": ") {
            Some((naming, rest)) if naming.contains(key) => rest,
            _ => &problem.message,
        };
        problem.message = format!("--set {set}: {message}");
        problem.line = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_typo_gets_its_nearest_key_and_a_stranger_none() {
        let message = "unknown field `gravty`, expected one of `boundary`, `gravity`, `min`";
        assert_eq!(nearest_key(message).as_deref(), Some("gravity"));
        let message = "unknown field `zzzzzz`, expected one of `boundary`, `gravity`, `min`";
        assert_eq!(nearest_key(message), None);
    }

    #[test]
    fn a_line_is_replaced_keeping_the_line_numbers() {
        let text = replace_line("[world]\nmin = \"x\"\nmax = 2\n", 2, "min = 1");
        assert_eq!(text, "[world]\nmin = 1\nmax = 2\n");
    }
}
