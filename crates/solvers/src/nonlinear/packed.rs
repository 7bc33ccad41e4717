//! The long vectors of a [`Checkpoint`](super::vocabulary::Checkpoint)
//! (displacements, integration-point states) packed for `serde`: written
//! as one string, `"f64le:"` followed by the base64 (RFC 4648, with
//! padding) of the values' little-endian IEEE 754 bytes; read from that
//! string or from a plain list of numbers (the checkpoints written before).
//!
//! A checkpoint is written after every increment. As a list of decimal
//! numbers the vectors cost about 20 characters and a shortest-round-trip
//! formatting each, which on a small model took about a fifth of the run
//! (the 2D DCB of `examples/plane`); packed they cost 10.7 characters and
//! a byte copy, and every value comes back bit for bit, NaN and infinities
//! included (JSON has no number for them).
//!
//! Use with `#[serde(with = "packed")]` on a `Vec<f64>` field.

use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserializer, Serializer};

/// What a packed string starts with.
const TAG: &str = "f64le:";
const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// `v` as `"f64le:BASE64"`.
pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&pack(v))
}

/// A packed string or a list of numbers.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    d.deserialize_any(PackedVisitor)
}

struct PackedVisitor;

impl<'de> Visitor<'de> for PackedVisitor {
    type Value = Vec<f64>;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a list of numbers or a string \"{TAG}<base64>\"")
    }
    fn visit_str<E: de::Error>(self, s: &str) -> Result<Vec<f64>, E> {
        unpack(s).map_err(E::custom)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
        let mut v = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 20));
        while let Some(x) = seq.next_element::<f64>()? {
            v.push(x);
        }
        Ok(v)
    }
}

/// `"f64le:"` and the base64 of the little-endian bytes of `v`. Whole
/// groups of three bytes first (four characters each, no branch), then the
/// last one or two bytes with their padding.
pub fn pack(v: &[f64]) -> String {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut out = Vec::with_capacity(TAG.len() + bytes.len().div_ceil(3) * 4);
    out.extend_from_slice(TAG.as_bytes());
    let letter = |n: u32, k: u32| ALPHABET[((n >> (18 - 6 * k)) & 63) as usize];
    let mut groups = bytes.chunks_exact(3);
    for g in &mut groups {
        let n = (u32::from(g[0]) << 16) | (u32::from(g[1]) << 8) | u32::from(g[2]);
        out.extend_from_slice(&[letter(n, 0), letter(n, 1), letter(n, 2), letter(n, 3)]);
    }
    let rest = groups.remainder();
    if !rest.is_empty() {
        let b1 = rest.get(1).copied().unwrap_or(0);
        let n = (u32::from(rest[0]) << 16) | (u32::from(b1) << 8);
        let third = if rest.len() == 2 { letter(n, 2) } else { b'=' };
        out.extend_from_slice(&[letter(n, 0), letter(n, 1), third, b'=']);
    }
    // every byte pushed is from TAG or ALPHABET: ASCII
    String::from_utf8(out).expect("base64 text is ASCII")
}

/// The values of a packed string (an error names what is wrong).
pub fn unpack(s: &str) -> Result<Vec<f64>, String> {
    let body = s
        .strip_prefix(TAG)
        .ok_or_else(|| format!("a packed vector starts with \"{TAG}\""))?
        .as_bytes();
    if body.len() % 4 != 0 {
        return Err(format!(
            "a packed vector's base64 has a length divisible by 4, not {}",
            body.len()
        ));
    }
    let value = |c: u8| -> Result<u32, String> {
        match c {
            b'A'..=b'Z' => Ok(u32::from(c - b'A')),
            b'a'..=b'z' => Ok(u32::from(c - b'a') + 26),
            b'0'..=b'9' => Ok(u32::from(c - b'0') + 52),
            b'+' => Ok(62),
            b'/' => Ok(63),
            _ => Err(format!(
                "`{}` is not a base64 character of a packed vector",
                c as char
            )),
        }
    };
    let mut bytes = Vec::with_capacity(body.len() / 4 * 3);
    for (i, quad) in body.chunks(4).enumerate() {
        let pad = quad.iter().rev().take_while(|&&c| c == b'=').count();
        if pad > 2 || (pad > 0 && i + 1 != body.len() / 4) {
            return Err("misplaced `=` in a packed vector".into());
        }
        let mut n = 0u32;
        for &c in &quad[..4 - pad] {
            n = (n << 6) | value(c)?;
        }
        n <<= 6 * pad as u32;
        let three = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        bytes.extend_from_slice(&three[..3 - pad]);
    }
    if bytes.len() % 8 != 0 {
        return Err(format!(
            "a packed vector holds whole 8-byte numbers, not {} bytes",
            bytes.len()
        ));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_come_back_bit_for_bit() {
        for v in [
            vec![],
            vec![1.0],
            vec![-0.0, 1e-300, f64::MAX],
            vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.1, 2.0 / 3.0],
        ] {
            let back = unpack(&pack(&v)).unwrap();
            assert_eq!(back.len(), v.len());
            for (a, b) in v.iter().zip(&back) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
        }
        // RFC 4648's own example: "foobar" is "Zm9vYmFy"; one f64 of the
        // bytes "foobar\0\0" packs as that plus "AAA="
        let x = f64::from_le_bytes(*b"foobar\0\0");
        assert_eq!(pack(&[x]), "f64le:Zm9vYmFyAAA=");
        // the other two remainders (16 and 24 bytes), as Python's
        // base64.b64encode(struct.pack("<2d", 1.0, -2.5)) and "<3d" with 0.1
        assert_eq!(pack(&[1.0, -2.5]), "f64le:AAAAAAAA8D8AAAAAAAAEwA==");
        assert_eq!(
            pack(&[1.0, -2.5, 0.1]),
            "f64le:AAAAAAAA8D8AAAAAAAAEwJqZmZmZmbk/"
        );
    }

    #[test]
    fn lists_and_packed_strings_both_read() {
        #[derive(serde::Deserialize, serde::Serialize)]
        struct S {
            #[serde(with = "super")]
            v: Vec<f64>,
        }
        let s: S = serde_json::from_str(r#"{"v": [1.5, -2.0]}"#).unwrap();
        assert_eq!(s.v, [1.5, -2.0]);
        let text = serde_json::to_string(&s).unwrap();
        assert!(text.contains("f64le:"), "{text}");
        let again: S = serde_json::from_str(&text).unwrap();
        assert_eq!(again.v, [1.5, -2.0]);
        for bad in [
            r#"{"v": "1.5"}"#,
            r#"{"v": "f64le:Zm9v"}"#,
            r#"{"v": "f64le:Z*9vYmFyAAA="}"#,
        ] {
            assert!(serde_json::from_str::<S>(bad).is_err(), "{bad}");
        }
    }
}
