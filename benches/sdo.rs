//! SDO throughput on the simulated bus, and the client's own CPU per frame.
//!
//! `cargo bench --bench sdo`. The end-to-end figures include the simulated devices; the
//! "client only" ones replay a recorded server side into the client state machine, which
//! is the cost a real bus would see on the host.

use canctl::bus::{Bus, Master, SdoOptions};
use canctl::canopen::sdo::{ObjectAccess, SdoClient, SdoServer};
use canctl::canopen::ObjAddr;
use canctl::sim::profiles::DOMAIN_SIZE;
use canctl::sim::{SimConfig, SimLink};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::time::Duration;

const DOMAIN: ObjAddr = ObjAddr::new(0x1F50, 1);

fn end_to_end(c: &mut Criterion) {
    let mut g = c.benchmark_group("sim 64 KiB upload");
    g.throughput(Throughput::Bytes(DOMAIN_SIZE as u64));
    for (name, block) in [("block", true), ("segmented", false)] {
        // Instant: this measures the host's CPU; benches/sim_bus.rs measures the bus.
        let mut bus = Master::new(SimLink::with_config(SimConfig::instant()), "sim".into());
        let mut opts = SdoOptions::new(Duration::from_secs(1));
        opts.block_upload = block;
        g.bench_function(name, |b| b.iter(|| assert_eq!(bus.sdo_upload(1, DOMAIN, &opts).unwrap().len(), DOMAIN_SIZE)));
    }
    g.finish();
}

struct One(Vec<u8>);

impl ObjectAccess for One {
    fn read(&mut self, _: ObjAddr) -> Result<Vec<u8>, u32> {
        Ok(self.0.clone())
    }
    fn write(&mut self, _: ObjAddr, d: &[u8]) -> Result<(), u32> {
        self.0 = d.to_vec();
        Ok(())
    }
    fn check_write(&self, _: ObjAddr, _: Option<usize>) -> Result<(), u32> {
        Ok(())
    }
}

/// The server's frames for one whole upload, recorded once.
fn record(block: bool) -> Vec<[u8; 8]> {
    let mut od = One(canctl::sim::profiles::domain_pattern(DOMAIN_SIZE));
    let mut server = SdoServer::new(true);
    let mut client = SdoClient::upload(DOMAIN, block);
    let mut to_server = vec![client.start()];
    let mut recorded = Vec::new();
    loop {
        let answers: Vec<[u8; 8]> = to_server.drain(..).flat_map(|r| server.handle(&r, &mut od)).collect();
        for a in answers {
            recorded.push(a);
            let step = client.on_response(&a).unwrap();
            to_server.extend(step.send);
            if step.done.is_some() {
                return recorded;
            }
        }
    }
}

fn client_only(c: &mut Criterion) {
    let mut g = c.benchmark_group("client only, 64 KiB upload");
    for (name, block) in [("block", true), ("segmented", false)] {
        let frames = record(block);
        g.throughput(Throughput::Elements(frames.len() as u64));
        g.bench_function(format!("{name} ({} frames in)", frames.len()), |b| {
            b.iter(|| {
                let mut client = SdoClient::upload(DOMAIN, block);
                client.start();
                let mut out = 0;
                for f in &frames {
                    let step = client.on_response(f).unwrap();
                    out += step.send.len();
                    if let Some(d) = step.done {
                        return (d.len(), out);
                    }
                }
                unreachable!()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, end_to_end, client_only);
criterion_main!(benches);
