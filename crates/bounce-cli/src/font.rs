//! The TrueType font `plots.png` and the frames' overlay write with: DejaVu Sans, from the
//! system (Debian's `fonts-dejavu-core`).

/// Where the font is looked for (Debian's fonts-dejavu-core first).
const FONTS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// The font file's bytes, if it is installed.
pub fn bytes() -> Option<Vec<u8>> {
    FONTS.iter().find_map(|p| std::fs::read(p).ok())
}
