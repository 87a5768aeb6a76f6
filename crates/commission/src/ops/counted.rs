//! A bus that counts the SDO transfers made through it and tells a [`Progress`] as they
//! go: a long procedure on one node shows that it is moving without reporting steps.

use super::progress::{ItemStatus, Progress};
use crate::bus::tap::{AfterSdo, Transfer};
use crate::bus::Bus;

/// `bus`, telling `progress` after each SDO transfer how many reads and writes `label`'s
/// work has made so far (as [`Progress::item`]).
pub fn counted<'a>(
    bus: &'a mut dyn Bus,
    label: &'a str,
    progress: &'a mut dyn Progress,
) -> AfterSdo<'a, impl FnMut(Transfer, u32) + 'a> {
    let (mut reads, mut writes) = (0, 0);
    AfterSdo::new(bus, move |kind, n| {
        match kind {
            Transfer::Upload => reads = n,
            Transfer::Download => writes = n,
            Transfer::Nmt => {}
        }
        progress.item(label, ItemStatus::Transfers { reads, writes });
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::SdoOptions;
    use crate::canopen::ObjAddr;
    use crate::connect::{BusAddr, OpenOptions};
    use std::time::Duration;

    #[derive(Default)]
    struct Items(Vec<(String, ItemStatus)>);

    impl Progress for Items {
        fn item(&mut self, item: &str, status: ItemStatus) {
            self.0.push((item.to_string(), status));
        }
    }

    #[test]
    fn each_transfer_is_counted_under_its_label() {
        let mut opts = OpenOptions::new(Duration::from_millis(500));
        opts.ephemeral = true;
        let mut bus = crate::connect::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap();
        let mut items = Items::default();
        {
            let mut c = counted(bus.as_mut(), "node 5", &mut items);
            let o = SdoOptions::new(Duration::from_millis(500));
            c.sdo_upload(5, ObjAddr::new(0x1000, 0), &o).unwrap();
            c.sdo_download(5, ObjAddr::new(0x1017, 0), &[100, 0], &o).unwrap();
        }
        let last = items.0.last().unwrap();
        assert_eq!((last.0.as_str(), last.1), ("node 5", ItemStatus::Transfers { reads: 1, writes: 1 }));
    }
}
