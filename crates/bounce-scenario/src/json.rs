//! The JSON the run's small files are written in (`summary.json`, a sweep's state points),
//! byte for byte as Python's `json` module writes it.

/// `s` as a JSON string, as Python's `json.dumps` writes it (`ensure_ascii`: everything
/// outside printable ASCII escaped), so that the bytes hash as Python's do (signac's ids).
pub fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 || (c as u32) > 0x7e => {
                let mut units = [0u16; 2];
                for unit in c.encode_utf16(&mut units) {
                    out.push_str(&format!("\\u{unit:04x}"));
                }
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::string;

    #[test]
    fn escapes_as_python_json_dumps() {
        // Each right-hand side is what `python3 -c 'import json; print(json.dumps(s))'` prints.
        assert_eq!(string("gas"), r#""gas""#);
        assert_eq!(string("a\"b\\c"), r#""a\"b\\c""#);
        assert_eq!(string("\n\r\t"), r#""\n\r\t""#);
        assert_eq!(string("\x7f\x1f"), r#""\u007f\u001f""#);
        assert_eq!(string("é"), r#""\u00e9""#);
        // Outside the basic plane: a surrogate pair, as Python writes it.
        assert_eq!(string("😀"), r#""\ud83d\ude00""#);
    }
}
