//! Colours in scenario files: `#rrggbb` or one of a few names.

/// An 8-bit RGB colour.
pub type Rgb = [u8; 3];

const NAMED: [(&str, Rgb); 10] = [
    ("red", [220, 50, 47]),
    ("orange", [240, 140, 30]),
    ("yellow", [240, 210, 40]),
    ("green", [60, 170, 80]),
    ("cyan", [40, 180, 200]),
    ("blue", [40, 100, 220]),
    ("purple", [140, 70, 200]),
    ("white", [240, 240, 240]),
    ("grey", [128, 128, 128]),
    ("black", [20, 20, 20]),
];

/// Parses `#rrggbb` or a name (red, orange, yellow, green, cyan, blue, purple, white, grey,
/// black).
pub fn parse_colour(text: &str) -> Result<Rgb, String> {
    let t = text.trim();
    if let Some(hex) = t.strip_prefix('#')
        && hex.len() == 6
        && let Ok(v) = u32::from_str_radix(hex, 16)
    {
        return Ok([(v >> 16) as u8, (v >> 8) as u8, v as u8]);
    }
    NAMED
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(t))
        .map(|(_, c)| *c)
        .ok_or_else(|| {
            format!(
                "color {text:?} is not #rrggbb or one of {}",
                NAMED.map(|(n, _)| n).join(", ")
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_and_names() {
        assert_eq!(parse_colour("#ff8000"), Ok([255, 128, 0]));
        assert_eq!(parse_colour("Blue"), Ok([40, 100, 220]));
        assert!(parse_colour("#ff80").unwrap_err().contains("#ff80"));
        assert!(parse_colour("mauve").is_err());
    }
}
