//! Command-line steering: `--set KEY=VALUE` and `--seed N` applied to scenario text.
//!
//! The text is edited in place (its layout, comments and table order kept: the order of the
//! particle tables decides the ids), then parsed and validated like any scenario file, so an
//! override is checked exactly as the file's own value would be.
//!
//! Keys are dotted paths: `world.coefficient_of_restitution`, `time.dt`, `output.frame_every`.
//! In arrays of tables the table is named by its 1-based number, as messages name it:
//! `gas.2.count`; with a single table the number may be left out (`gas.count`).

use toml_edit::{DocumentMut, Item, Value};

/// The comment an override leaves on the line it writes, so that a problem found on that line
/// names the override (`--set world.gravty=1`) rather than a line of the file.
pub(crate) const MARK: &str = "# --set ";

/// Applies `sets` (`KEY=VALUE` each, VALUE in TOML syntax, a bare word taken as a string) and
/// `seed` (every `[[gas]]` gets `seed = N + its index`) to `text`. Errors name the override.
pub fn apply(text: &str, sets: &[String], seed: Option<u64>) -> Result<String, String> {
    if sets.is_empty() && seed.is_none() {
        return Ok(text.to_string());
    }
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| format!("the scenario is not valid TOML: {e}"))?;
    for set in sets {
        let (key, raw) = set
            .split_once('=')
            .ok_or_else(|| format!("--set {set}: expected KEY=VALUE"))?;
        let (key, raw) = (key.trim(), raw.trim());
        let value = parse_value(raw);
        let path: Vec<&str> = key.split('.').collect();
        if path.iter().any(|p| p.is_empty()) {
            return Err(format!("--set {set}: empty part in the key {key:?}"));
        }
        set_path(doc.as_item_mut(), &path, value, Some(set))
            .map_err(|e| format!("--set {set}: {e}"))?;
    }
    if let Some(seed) = seed
        && let Some(gases) = doc.get_mut("gas").and_then(Item::as_array_of_tables_mut)
    {
        for (k, gas) in gases.iter_mut().enumerate() {
            let value = seed.wrapping_add(k as u64);
            let value =
                i64::try_from(value).map_err(|_| format!("--seed {seed}: must be below 2^63"))?;
            gas["seed"] = toml_edit::value(value);
        }
    }
    Ok(doc.to_string())
}

/// A value in TOML syntax (`0.9`, `[0.0, -9.8]`, `"walls"`), or a bare word as a string.
fn parse_value(raw: &str) -> Value {
    raw.parse::<Value>()
        .unwrap_or_else(|_| Value::from(raw.to_string()))
}

fn set_path(
    item: &mut Item,
    path: &[&str],
    value: Value,
    mark: Option<&str>,
) -> Result<(), String> {
    let (head, rest) = path.split_first().expect("non-empty path");
    if let Some(tables) = item.as_array_of_tables_mut() {
        // A 1-based table number, or the only table.
        let (index, rest) = match head.parse::<usize>() {
            Ok(n) => (n, rest),
            Err(_) if tables.len() == 1 => (1, path),
            Err(_) => {
                return Err(format!(
                    "there are {} tables here: name one by its number (e.g. {}.{head})",
                    tables.len(),
                    1
                ));
            }
        };
        let count = tables.len();
        let table = index
            .checked_sub(1)
            .and_then(|i| tables.get_mut(i))
            .ok_or_else(|| format!("there is no table #{index} (there are {count})"))?;
        if rest.is_empty() {
            return Err("a whole table cannot be set".into());
        }
        return set_path_in_table(table, rest, value, mark);
    }
    // A comment cannot stand inside an inline table: no mark there.
    let mark = mark.filter(|_| !item.is_inline_table());
    let table = item
        .as_table_like_mut()
        .ok_or_else(|| format!("{head:?} is inside a value, not a table"))?;
    set_path_in_table(table, path, value, mark)
}

/// Sets `path` inside `table`, making tables on the way; the value written carries the
/// override's [`MARK`] where a comment can stand.
fn set_path_in_table(
    table: &mut dyn toml_edit::TableLike,
    path: &[&str],
    mut value: Value,
    mark: Option<&str>,
) -> Result<(), String> {
    let (head, rest) = path.split_first().expect("non-empty path");
    if rest.is_empty() {
        if let Some(set) = mark {
            value.decor_mut().set_suffix(format!(" {MARK}{set}"));
        }
        table.insert(head, Item::Value(value));
        return Ok(());
    }
    if table.get(head).is_none() {
        table.insert(head, Item::Table(toml_edit::Table::new()));
    }
    set_path(table.get_mut(head).expect("inserted"), rest, value, mark)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "# a comment\n[world]\nmin = [0.0, 0.0]\nmax = [10.0, 10.0]\n\
                        [time]\ndt = 0.01\nsteps = 10\n\n[[gas]]\ncount = 5\nradius = 0.2\n\
                        speed = 1.0\n\n[[disc]]\nposition = [1.0, 1.0]\nradius = 0.5\n\n\
                        [[gas]]\ncount = 3\nradius = 0.1\nspeed = 1.0\n";

    #[test]
    fn sets_values_and_keeps_the_layout() {
        let out = apply(
            TEXT,
            &[
                "world.coefficient_of_restitution=0.9".into(),
                "time.dt = 0.001".into(),
                "gas.2.count=7".into(),
                "world.boundary=periodic".into(),
            ],
            None,
        )
        .unwrap();
        let scenario = crate::parse(&out, "s").unwrap();
        assert_eq!(scenario.world.coefficient_of_restitution, 0.9);
        assert_eq!(scenario.time.dt, 0.001);
        assert_eq!(scenario.gas[1].get_ref().count, 7);
        assert_eq!(scenario.world.boundary, crate::BoundaryKind::Periodic);
        // Table order (and so the ids) is unchanged: gas, disc, gas.
        let (g1, d, g2) = (
            out.find("[[gas]]").unwrap(),
            out.find("[[disc]]").unwrap(),
            out.rfind("[[gas]]").unwrap(),
        );
        assert!(g1 < d && d < g2 && out.starts_with("# a comment"));
    }

    #[test]
    fn seeds_every_gas_and_refuses_bad_keys() {
        let out = apply(TEXT, &[], Some(41)).unwrap();
        let scenario = crate::parse(&out, "s").unwrap();
        let seeds: Vec<u64> = scenario.gas.iter().map(|g| g.get_ref().seed).collect();
        assert_eq!(seeds, vec![41, 42]);
        assert!(
            apply(TEXT, &["gas.count=3".into()], None)
                .unwrap_err()
                .contains("2 tables")
        );
        assert!(
            apply(TEXT, &["gas.9.count=3".into()], None)
                .unwrap_err()
                .contains("no table #9")
        );
        assert!(
            apply(TEXT, &["time.dt".into()], None)
                .unwrap_err()
                .contains("KEY=VALUE")
        );
        // An unknown field is inserted, then refused by validation like the file's own.
        let out = apply(TEXT, &["world.colour=3".into()], None).unwrap();
        let e = crate::parse(&out, "s").unwrap_err().to_string();
        assert!(e.contains("colour"), "{e}");
        // A bad value too.
        let out = apply(TEXT, &["time.dt=-1".into()], None).unwrap();
        let e = crate::parse(&out, "s").unwrap_err().to_string();
        assert!(e.contains("time.dt = -1"), "{e}");
    }
}
