//! Packed words: fields, layouts, arbitrary-width words and the `$readmemh` text format.

use std::path::Path;

use serde_json::{json, Value};

use super::VectorError;

/// One field of a packed word.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    /// Name (`v3_a`, `fx`, `acc_r`, …).
    pub name: String,
    /// Offset of the least significant bit (bit 0 is the word's least significant bit).
    pub offset: u32,
    /// Width in bits.
    pub width: u32,
    /// Fractional bits of the value.
    pub frac_bits: u32,
    /// Two's complement (`true`) or unsigned.
    pub signed: bool,
    /// Format and meaning.
    pub meaning: String,
}

/// The fields of a word, packed from bit 0 upwards in order.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Layout {
    /// The fields, lowest offset first.
    pub fields: Vec<Field>,
}

impl Layout {
    /// Appends an unsigned field above the last one.
    pub(super) fn push(&mut self, name: String, width: u32, frac_bits: u32, meaning: &str) {
        self.push_field(name, width, frac_bits, false, meaning);
    }

    /// Appends a two's complement field above the last one.
    pub(super) fn push_signed(&mut self, name: String, width: u32, frac_bits: u32, meaning: &str) {
        self.push_field(name, width, frac_bits, true, meaning);
    }

    fn push_field(
        &mut self,
        name: String,
        width: u32,
        frac_bits: u32,
        signed: bool,
        meaning: &str,
    ) {
        let offset = self.width();
        self.fields.push(Field {
            name,
            offset,
            width,
            frac_bits,
            signed,
            meaning: meaning.to_string(),
        });
    }

    /// A layout of one unsigned field of `width` bits (a table entry).
    pub(super) fn single(name: &str, width: u32) -> Self {
        let mut l = Self::default();
        l.push(name.to_string(), width, 0, "");
        l
    }

    /// Total width in bits.
    pub fn width(&self) -> u32 {
        self.fields.last().map_or(0, |f| f.offset + f.width)
    }

    /// Hex digits per line (`⌈width/4⌉`).
    pub fn hex_digits(&self) -> usize {
        self.width().div_ceil(4) as usize
    }

    /// Packs one value per field (each masked to its width) into a word.
    pub fn pack(&self, values: &[u64]) -> Word {
        let mut w = Word::zero(self.width());
        for (f, &v) in self.fields.iter().zip(values) {
            w.set(f.offset, f.width, v);
        }
        w
    }

    /// The value of each field of a word.
    pub fn unpack(&self, w: &Word) -> Vec<u64> {
        self.fields
            .iter()
            .map(|f| w.get(f.offset, f.width))
            .collect()
    }
}

pub(super) fn push_u88(l: &mut Layout, prefix: &str) {
    for ch in ["r", "g", "b"] {
        l.push(
            format!("{prefix}{ch}"),
            16,
            8,
            "U8.8 associated color C̃ (raw/256 u8 levels; ≤ α)",
        );
    }
    l.push(
        format!("{prefix}a"),
        16,
        8,
        "U8.8 opacity α (ONE = 65280 is opaque)",
    );
}

/// A word of any width, as little-endian 64-bit limbs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Word {
    limbs: Vec<u64>,
}

impl Word {
    /// A zero word of `width` bits.
    pub fn zero(width: u32) -> Self {
        Self {
            limbs: vec![0; width.div_ceil(64).max(1) as usize],
        }
    }

    /// Sets bits `offset..offset + width` (`width ≤ 64`) to `value` (masked).
    pub fn set(&mut self, offset: u32, width: u32, value: u64) {
        for b in 0..width.min(64) {
            let bit = (value >> b) & 1;
            let pos = offset + b;
            if let Some(l) = self.limbs.get_mut((pos / 64) as usize) {
                *l = (*l & !(1 << (pos % 64))) | (bit << (pos % 64));
            }
        }
    }

    /// Bits `offset..offset + width` (`width ≤ 64`).
    pub fn get(&self, offset: u32, width: u32) -> u64 {
        (0..width.min(64)).fold(0, |acc, b| {
            let pos = offset + b;
            let bit = self
                .limbs
                .get((pos / 64) as usize)
                .map_or(0, |l| (l >> (pos % 64)) & 1);
            acc | (bit << b)
        })
    }

    /// `digits` lowercase hex digits, most significant first.
    pub fn to_hex(&self, digits: usize) -> String {
        (0..digits)
            .rev()
            .map(|d| {
                let nib = self.get(d as u32 * 4, 4) as u32;
                char::from_digit(nib, 16).unwrap_or('0')
            })
            .collect()
    }

    /// Parses exactly `digits` hex digits into a word of `width` bits; `None` if the text is
    /// not such a word or sets a bit at or above `width`.
    pub fn from_hex(text: &str, digits: usize, width: u32) -> Option<Self> {
        if text.len() != digits {
            return None;
        }
        let mut w = Word::zero(digits as u32 * 4);
        for (d, c) in text.chars().rev().enumerate() {
            w.set(d as u32 * 4, 4, u64::from(c.to_digit(16)?));
        }
        let top = digits as u32 * 4;
        if (width..top).any(|b| w.get(b, 1) != 0) {
            return None;
        }
        w.limbs.truncate(width.div_ceil(64).max(1) as usize);
        Some(w)
    }
}

/// The text of a `.hex` file: one word per line.
pub fn hex_text(layout: &Layout, words: &[Word]) -> String {
    let d = layout.hex_digits();
    let mut s = String::with_capacity(words.len() * (d + 1));
    for w in words {
        s.push_str(&w.to_hex(d));
        s.push('\n');
    }
    s
}

/// Reads a `.hex` file written with `layout` (blank lines and `//` comments skipped).
///
/// # Errors
/// [`VectorError::Read`] if it cannot be read; [`VectorError::Parse`] for a line that is not one
/// word of the layout's width.
pub fn read_hex(path: &Path, layout: &Layout) -> Result<Vec<Word>, VectorError> {
    let text = std::fs::read_to_string(path).map_err(|source| VectorError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut words = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split("//").next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let w = Word::from_hex(line, layout.hex_digits(), layout.width()).ok_or_else(|| {
            VectorError::Parse {
                path: path.to_path_buf(),
                message: format!(
                    "line {}: expected {} hex digits of a {}-bit word, found '{line}'",
                    n + 1,
                    layout.hex_digits(),
                    layout.width()
                ),
            }
        })?;
        words.push(w);
    }
    Ok(words)
}

pub(super) fn layout_json(l: &Layout, file: &str) -> Value {
    json!({
        "file": file,
        "word_bits": l.width(),
        "hex_digits": l.hex_digits(),
        "packing": "fields from bit 0 (least significant) upwards; one word per line, most significant hex digit first",
        "fields": l.fields.iter().map(|f| json!({
            "name": f.name,
            "offset": f.offset,
            "width": f.width,
            "frac_bits": f.frac_bits,
            "signed": f.signed,
            "meaning": f.meaning,
        })).collect::<Vec<_>>(),
    })
}
