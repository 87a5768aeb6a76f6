//! Decoding and formatting PDOs: the sensor's 6-byte position+speed PDO (seed 001 figure
//! 24) into CSV rows and JSON lines, per frame. `cargo bench --bench pdo`.

use canctl::canopen::pdo::{Field, Layout};
use canctl::canopen::DataType;
use canctl::output::{Format, RecordWriter};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};

fn layout() -> Layout {
    Layout {
        cob_id: 0x185,
        fields: vec![
            Field::mapped(0x6020_0120, DataType::I32, "position"),
            Field::mapped(0x6030_0110, DataType::I16, "speed"),
        ],
    }
}

fn decode_and_format(c: &mut Criterion) {
    let l = layout();
    let (csv, json) = (RecordWriter::new(&l, Format::Csv), RecordWriter::new(&l, Format::Json));
    let frame = [0x48, 0xE8, 0x01, 0x00, 0x9C, 0xFF];
    let mut g = c.benchmark_group("6-byte PDO, decode + format");
    g.throughput(Throughput::Elements(1));
    let mut out = String::with_capacity(256);
    g.bench_function("csv", |b| {
        b.iter(|| {
            out.clear();
            let v = l.decode(black_box(&frame)).unwrap();
            csv.csv(&mut out, black_box(1_795_318_672_209), 1, &v);
            out.len()
        })
    });
    g.bench_function("json", |b| {
        b.iter(|| {
            out.clear();
            let v = l.decode(black_box(&frame)).unwrap();
            json.json(&mut out, black_box(1_795_318_672_209), 5, 1, &v);
            out.len()
        })
    });
    g.finish();
}

criterion_group!(benches, decode_and_format);
criterion_main!(benches);
