//! PDO mapping (CiA 301 §7.2.2): which object bits travel where in a PDO, and the
//! bit-exact packing of values into frames and out of them.

use super::types::{DataType, Value};
use super::ObjAddr;

/// One mapping entry: `index << 16 | sub << 8 | bits`.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The mapped object.
    pub addr: ObjAddr,
    /// Its width in the PDO.
    pub bits: u8,
    /// How to read its bits.
    pub dtype: DataType,
    /// Its name, for reports.
    pub name: String,
}

impl Field {
    /// The field a raw mapping entry (0x60200120) describes, read as `dtype`.
    pub fn mapped(raw: u32, dtype: DataType, name: &str) -> Field {
        let (addr, bits) = mapping_entry(raw);
        Field { addr, bits, dtype, name: name.into() }
    }
}

/// A PDO mapping entry as CiA 301 codes it, read: the object and its length in bits.
pub fn mapping_entry(raw: u32) -> (ObjAddr, u8) {
    (ObjAddr::new((raw >> 16) as u16, (raw >> 8) as u8), raw as u8)
}

/// A PDO mapping entry as CiA 301 codes it: index, sub-index, then the length in bits.
pub fn mapping_raw(addr: ObjAddr, bits: u8) -> u32 {
    (addr.index as u32) << 16 | (addr.sub as u32) << 8 | bits as u32
}

/// The type a field of `bits` bits has when no dictionary says: unsigned of that width.
pub fn default_type(bits: u8) -> DataType {
    match bits {
        1 => DataType::Bool,
        2..=8 => DataType::U8,
        9..=16 => DataType::U16,
        17..=32 => DataType::U32,
        _ => DataType::U64,
    }
}

/// A PDO's layout and how to read it.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The COB-ID the PDO is sent on.
    pub cob_id: u16,
    /// Its fields, in mapping order.
    pub fields: Vec<Field>,
}

/// A frame whose length is not the layout's.
#[derive(Debug, PartialEq, Eq)]
pub struct LengthMismatch {
    /// Bytes received.
    pub got: usize,
    /// Bytes the layout needs.
    pub want: usize,
}

impl Layout {
    /// The bits mapped, in all.
    pub fn bits(&self) -> usize {
        self.fields.iter().map(|f| f.bits as usize).sum()
    }

    /// Bytes a frame of this PDO carries.
    pub fn len(&self) -> usize {
        self.bits().div_ceil(8)
    }

    /// Whether nothing is mapped.
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }

    /// The fields' values. A frame of another length than the mapping says is not
    /// decoded: its bytes would be read as something they are not.
    pub fn decode(&self, data: &[u8]) -> Result<Vec<Value>, LengthMismatch> {
        if data.len() != self.len() {
            return Err(LengthMismatch { got: data.len(), want: self.len() });
        }
        let mut word = [0u8; 8];
        word[..data.len()].copy_from_slice(data);
        let all = u64::from_le_bytes(word);
        let mut at = 0u32;
        Ok(self
            .fields
            .iter()
            .map(|f| {
                let bits = f.bits as u32;
                let raw = if bits == 64 { all } else { (all >> at) & ((1u64 << bits) - 1) };
                at += bits;
                field_value(raw, bits, f.dtype)
            })
            .collect())
    }
}

fn field_value(raw: u64, bits: u32, dtype: DataType) -> Value {
    match dtype {
        DataType::Bool => Value::Bool(raw != 0),
        DataType::R32 if bits == 32 => Value::Real(f32::from_bits(raw as u32) as f64, dtype),
        DataType::R64 if bits == 64 => Value::Real(f64::from_bits(raw), dtype),
        DataType::TimeOfDay | DataType::TimeDifference if bits == 48 => {
            dtype.decode(&raw.to_le_bytes()[..6]).expect("six bytes")
        }
        t if t.is_signed() => {
            let shift = 64 - bits;
            Value::Int(((raw << shift) as i64) >> shift)
        }
        _ => Value::Uint(raw),
    }
}

/// Pack field values (little-endian object bytes) into a PDO payload.
pub fn encode(fields: &[(u8, Vec<u8>)]) -> Vec<u8> {
    let mut all: u64 = 0;
    let mut at = 0u32;
    for (bits, bytes) in fields {
        let mut word = [0u8; 8];
        let n = bytes.len().min(8);
        word[..n].copy_from_slice(&bytes[..n]);
        let v = u64::from_le_bytes(word);
        let mask = if *bits == 64 { u64::MAX } else { (1u64 << bits) - 1 };
        all |= (v & mask) << at;
        at += *bits as u32;
    }
    all.to_le_bytes()[..(at as usize).div_ceil(8)].to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mh_tpdo1() -> Layout {
        // Seed 001 0x1A00: 0x60200120 (position, 32 bits), 0x60300110 (speed, 16 bits).
        Layout {
            cob_id: 0x185,
            fields: vec![
                Field::mapped(0x6020_0120, DataType::I32, "position"),
                Field::mapped(0x6030_0110, DataType::I16, "speed"),
            ],
        }
    }

    #[test]
    fn seed_001_figure_24_position_and_speed() {
        let l = mh_tpdo1();
        assert_eq!(l.len(), 6);
        // Pos LSB..MSB, Speed LSB, MSB
        let values = l.decode(&[0x48, 0xE8, 0x01, 0x00, 0x9C, 0xFF]).unwrap();
        assert_eq!(values, [Value::Int(125_000), Value::Int(-100)]);
        assert_eq!(l.decode(&[0; 8]), Err(LengthMismatch { got: 8, want: 6 }));
        assert_eq!(
            encode(&[(32, 125_000i32.to_le_bytes().to_vec()), (16, (-100i16).to_le_bytes().to_vec())]),
            [0x48, 0xE8, 0x01, 0x00, 0x9C, 0xFF]
        );
    }

    #[test]
    fn odd_bit_fields_round_trip() {
        let l = Layout {
            cob_id: 0x18A,
            fields: vec![
                Field { addr: ObjAddr::new(0x2000, 1), bits: 1, dtype: DataType::Bool, name: "a".into() },
                Field { addr: ObjAddr::new(0x2000, 2), bits: 3, dtype: DataType::I8, name: "b".into() },
                Field { addr: ObjAddr::new(0x2000, 3), bits: 12, dtype: DataType::U16, name: "c".into() },
                Field { addr: ObjAddr::new(0x2000, 4), bits: 32, dtype: DataType::R32, name: "d".into() },
            ],
        };
        let bytes =
            encode(&[(1, vec![1]), (3, vec![0xFD]), (12, vec![0x34, 0x0A]), (32, 1.5f32.to_le_bytes().to_vec())]);
        assert_eq!(bytes.len(), 6);
        assert_eq!(
            l.decode(&bytes).unwrap(),
            [Value::Bool(true), Value::Int(-3), Value::Uint(0xA34), Value::Real(1.5, DataType::R32)]
        );
        assert_eq!(mapping_raw(ObjAddr::new(0x6020, 1), 32), 0x6020_0120);
    }
}
