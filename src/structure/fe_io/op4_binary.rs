//! NASTRAN OUTPUT4, binary form (Fortran unformatted sequential records, either endianness).
//!
//! Each record is `len payload len` with `len` a 4-byte byte count. Header record (24 bytes):
//! `ncols nrows form type` (4-byte integers) and the 8-character name. Column records:
//! `icol irow nw` then `nw` 4-byte words of data (2 words per double value, type 2). Dense
//! columns (`irow > 0`) hold consecutive rows from `irow`; sparse columns (`irow = 0`) hold
//! strings announced by `IS = irow + 65536 (L + 1)` (L words follow) or, for BIGMAT
//! (`nrows < 0`), by the pair `L irow` (L - 1 words follow). The matrix ends with a column
//! record whose `icol` exceeds `ncols`. Real types 1 and 2, forms 1, 2 and 6.
//!
//! Errors in binary files carry line 0 and the 1-based byte offset in `column`.

use std::path::Path;

use super::assemble::{RawMatrix, Storage};
use super::error::{FeReadError, SourceLocation};
use super::op4::Op4Matrix;

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
    big_endian: bool,
    path: &'a Path,
}

impl Reader<'_> {
    fn loc(&self, at: usize) -> SourceLocation {
        SourceLocation::at(self.path, 0, at + 1)
    }

    fn i32_at(&self, at: usize) -> Option<i32> {
        let b: [u8; 4] = self.bytes.get(at..at + 4)?.try_into().ok()?;
        Some(if self.big_endian {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        })
    }

    /// The next record: byte offset and length of its payload.
    fn record(&mut self) -> Result<Option<(usize, usize)>, FeReadError> {
        if self.pos >= self.bytes.len() {
            return Ok(None);
        }
        let start = self.pos;
        let len = self
            .i32_at(start)
            .ok_or_else(|| FeReadError::Truncated(self.loc(start), "record length cut short"))?;
        let len = usize::try_from(len).map_err(|_| {
            FeReadError::BadRecord(self.loc(start), format!("negative record length {len}"))
        })?;
        let end = start + 4 + len;
        let trailer = self.i32_at(end).ok_or_else(|| {
            FeReadError::Truncated(
                self.loc(self.bytes.len()),
                format!("record at byte {} announces {len} bytes", start + 1),
            )
        })?;
        if trailer as usize != len {
            return Err(FeReadError::BadRecord(
                self.loc(end),
                format!("record trailer {trailer} differs from header {len}"),
            ));
        }
        self.pos = end + 4;
        Ok(Some((start + 4, len)))
    }
}

/// Does `bytes` start like a binary OP4 file (a first record of 24 bytes)?
pub fn looks_like_binary_op4(bytes: &[u8]) -> bool {
    bytes.len() >= 4 && (bytes[..4] == 24i32.to_le_bytes() || bytes[..4] == 24i32.to_be_bytes())
}

/// Parses every matrix of a binary OP4 file.
pub fn parse_op4_binary(bytes: &[u8], path: &Path) -> Result<Vec<Op4Matrix>, FeReadError> {
    let big_endian = bytes.len() >= 4 && bytes[..4] == 24i32.to_be_bytes();
    let mut r = Reader {
        bytes,
        pos: 0,
        big_endian,
        path,
    };
    let mut out = Vec::new();
    while let Some((hpos, hlen)) = r.record()? {
        if hlen != 24 {
            return Err(FeReadError::UnknownHeader(
                r.loc(hpos),
                format!("header record of {hlen} bytes (expected 24)"),
            ));
        }
        let word = |k: usize| r.i32_at(hpos + 4 * k).unwrap_or(0) as i64;
        let (ncols, nrows_signed, form, typ) = (word(0), word(1), word(2), word(3));
        let name = String::from_utf8_lossy(&bytes[hpos + 16..hpos + 24])
            .trim()
            .to_string();
        if ncols <= 0 || nrows_signed == 0 {
            return Err(FeReadError::UnknownHeader(
                r.loc(hpos),
                format!("matrix {name}: {ncols} columns, {nrows_signed} rows"),
            ));
        }
        let value_words = match typ {
            1 => 1,
            2 => 2,
            _ => {
                return Err(FeReadError::Unsupported(
                    r.loc(hpos),
                    format!("matrix {name} has type {typ}; only real types 1 and 2 are read"),
                ));
            }
        };
        let storage = match form {
            6 => Storage::Symmetric,
            1 | 2 => Storage::General,
            _ => {
                return Err(FeReadError::Unsupported(
                    r.loc(hpos),
                    format!("matrix {name} has form {form}"),
                ));
            }
        };
        let bigmat = nrows_signed < 0;
        let (nrows, ncols) = (nrows_signed.unsigned_abs() as usize, ncols as usize);
        let mut entries = Vec::new();
        loop {
            let Some((cpos, rlen)) = r.record()? else {
                return Err(FeReadError::Truncated(
                    r.loc(bytes.len()),
                    format!("matrix {name} has no terminating column record"),
                ));
            };
            if rlen < 12 || rlen % 4 != 0 {
                return Err(FeReadError::BadRecord(
                    r.loc(cpos),
                    format!("column record of {rlen} bytes"),
                ));
            }
            let w = |k: usize| r.i32_at(cpos + 4 * k).unwrap_or(0) as i64;
            let (icol, irow, nw) = (w(0), w(1), w(2));
            if icol as usize > ncols {
                break;
            }
            let n_words = rlen / 4 - 3;
            if icol < 1 || irow < 0 || nw as usize != n_words {
                return Err(FeReadError::BadRecord(
                    r.loc(cpos),
                    format!(
                        "column record icol {icol} irow {irow} nw {nw} with {n_words} data words"
                    ),
                ));
            }
            let value = |word: usize| -> f64 {
                let at = cpos + 12 + 4 * word;
                if value_words == 1 {
                    let b: [u8; 4] = bytes[at..at + 4].try_into().unwrap_or([0; 4]);
                    f64::from(if big_endian {
                        f32::from_be_bytes(b)
                    } else {
                        f32::from_le_bytes(b)
                    })
                } else {
                    let b: [u8; 8] = bytes[at..at + 8].try_into().unwrap_or([0; 8]);
                    if big_endian {
                        f64::from_be_bytes(b)
                    } else {
                        f64::from_le_bytes(b)
                    }
                }
            };
            let col = icol as usize - 1;
            let push = |row: usize,
                        word: usize,
                        entries: &mut Vec<(usize, usize, f64, usize)>|
             -> Result<(), FeReadError> {
                let v = value(word);
                let at = cpos + 12 + 4 * word;
                if !v.is_finite() {
                    return Err(FeReadError::NonFinite(
                        r.loc(at),
                        format!("matrix {name} ({}, {})", row + 1, col + 1),
                    ));
                }
                if row >= nrows {
                    return Err(FeReadError::IndexOutOfRange(
                        r.loc(at),
                        format!("row {} of matrix {name} with {nrows} rows", row + 1),
                    ));
                }
                if v != 0.0 {
                    entries.push((row, col, v, 0));
                }
                Ok(())
            };
            if irow > 0 {
                if n_words % value_words != 0 {
                    return Err(FeReadError::BadRecord(
                        r.loc(cpos),
                        format!("{n_words} words is not a whole number of values"),
                    ));
                }
                for k in 0..n_words / value_words {
                    push(irow as usize - 1 + k, k * value_words, &mut entries)?;
                }
            } else {
                let mut k = 0;
                while k < n_words {
                    let (start_row, len_words, header) = if bigmat {
                        let l = r.i32_at(cpos + 12 + 4 * k).unwrap_or(0) as i64;
                        let row = r.i32_at(cpos + 16 + 4 * k).unwrap_or(0) as i64;
                        (row, l - 1, 2)
                    } else {
                        let is = r.i32_at(cpos + 12 + 4 * k).unwrap_or(0) as i64;
                        (is % 65536, is / 65536 - 1, 1)
                    };
                    let first = k + header;
                    if start_row < 1
                        || len_words < 0
                        || first + len_words as usize > n_words
                        || len_words as usize % value_words != 0
                    {
                        return Err(FeReadError::BadRecord(
                            r.loc(cpos + 12 + 4 * k),
                            format!("bad string header in column {icol} of {name}"),
                        ));
                    }
                    for v in 0..len_words as usize / value_words {
                        push(
                            start_row as usize - 1 + v,
                            first + v * value_words,
                            &mut entries,
                        )?;
                    }
                    k = first + len_words as usize;
                }
            }
        }
        out.push(Op4Matrix {
            name,
            form,
            matrix: RawMatrix {
                path: path.to_path_buf(),
                header_line: 0,
                nrows,
                ncols,
                storage,
                entries,
            },
        });
    }
    if out.is_empty() {
        return Err(FeReadError::Truncated(r.loc(0), "empty OP4 file"));
    }
    Ok(out)
}
