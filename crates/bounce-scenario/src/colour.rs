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

/// A perceptually ordered ramp, dark blue through teal and green to yellow, for `t` in
/// [0, 1] (clamped; NaN gives the top): how frames colour speed and radius.
pub fn ramp(t: f64) -> Rgb {
    const STOPS: [Rgb; 5] = [
        [59, 76, 192],
        [40, 140, 200],
        [60, 180, 140],
        [170, 210, 60],
        [250, 230, 40],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    } * (STOPS.len() - 1) as f64;
    let k = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    [0, 1, 2].map(|c| mix(STOPS[k][c], STOPS[k + 1][c]))
}

/// A diverging ramp for a signed `t` in [-1, 1] (clamped; NaN gives grey): blue for
/// clockwise, light grey for none, red for counter-clockwise: how frames colour spin.
pub fn spin_ramp(t: f64) -> Rgb {
    const CLOCKWISE: Rgb = [59, 76, 192];
    const STILL: Rgb = [220, 220, 220];
    const ANTICLOCKWISE: Rgb = [180, 4, 38];
    let t = if t.is_finite() {
        t.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let (end, f) = if t < 0.0 {
        (CLOCKWISE, -t)
    } else {
        (ANTICLOCKWISE, t)
    };
    [0, 1, 2].map(|c| (STILL[c] as f64 + (end[c] as f64 - STILL[c] as f64) * f).round() as u8)
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

    #[test]
    fn spin_ramp_runs_from_blue_through_grey_to_red() {
        assert_eq!(spin_ramp(-1.0), [59, 76, 192]);
        assert_eq!(spin_ramp(-7.0), [59, 76, 192]);
        assert_eq!(spin_ramp(0.0), [220, 220, 220]);
        assert_eq!(spin_ramp(f64::NAN), [220, 220, 220]);
        assert_eq!(spin_ramp(1.0), [180, 4, 38]);
        assert_eq!(spin_ramp(0.5), [200, 112, 129]);
    }

    #[test]
    fn ramp_runs_from_blue_to_yellow() {
        assert_eq!(ramp(0.0), [59, 76, 192]);
        assert_eq!(ramp(1.0), [250, 230, 40]);
        assert_eq!(ramp(7.0), ramp(1.0));
        assert_eq!(ramp(f64::NAN), ramp(1.0));
    }
}
