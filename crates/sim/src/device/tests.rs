use super::*;

/// Expedited SDO download to the drive (node 1); returns the answer's bytes.
fn write(d: &mut Device, index: u16, sub: u8, value: &[u8]) -> Vec<u8> {
    let mut req = [0u8; 8];
    req[0] = 0x23 | ((4 - value.len() as u8) << 2);
    req[1..3].copy_from_slice(&index.to_le_bytes());
    req[3] = sub;
    req[4..4 + value.len()].copy_from_slice(value);
    let out = d.on_frame(&Frame::new(0x601, &req));
    assert_eq!(out.len(), 1);
    out[0].data().to_vec()
}

#[test]
fn a_mapping_longer_than_a_pdo_is_refused_when_its_count_is_written() {
    let mut d = Device::new(super::super::profiles::drive(), Some(1), 2);
    assert_eq!(write(&mut d, 0x1800, 1, &0x8000_0181u32.to_le_bytes())[0], 0x60);
    assert_eq!(write(&mut d, 0x1A00, 0, &[0])[0], 0x60);
    for (sub, raw) in [(1u8, 0x6064_0020u32), (2, 0x606C_0020), (3, 0x6041_0010)] {
        assert_eq!(write(&mut d, 0x1A00, sub, &raw.to_le_bytes())[0], 0x60);
    }
    // 80 bits: abort 0x06040042 on 0x1A00:0.
    assert_eq!(write(&mut d, 0x1A00, 0, &[3]), [0x80, 0x00, 0x1A, 0x00, 0x42, 0x00, 0x04, 0x06]);
    // 64 bits fit.
    assert_eq!(write(&mut d, 0x1A00, 0, &[2])[0], 0x60);
    // An object the device does not have: 0x06040041.
    assert_eq!(write(&mut d, 0x1A00, 0, &[0])[0], 0x60);
    write(&mut d, 0x1A00, 1, &0x5123_0020u32.to_le_bytes());
    assert_eq!(write(&mut d, 0x1A00, 0, &[1]), [0x80, 0x00, 0x1A, 0x00, 0x41, 0x00, 0x04, 0x06]);
}

fn statusword(d: &Device) -> u16 {
    d.objects().u16_value(cia402::STATUSWORD).unwrap()
}

#[test]
fn the_drive_walks_the_cia402_state_machine_on_controlword_writes() {
    let mut d = Device::new(super::super::profiles::drive(), Some(1), 2);
    assert_eq!(statusword(&d), 0x0540);
    for (cw, sw) in [(0x06u16, 0x0521u16), (0x07, 0x0523), (0x0F, 0x0537), (0x02, 0x0517), (0x00, 0x0540)] {
        assert_eq!(write(&mut d, 0x6040, 0, &cw.to_le_bytes())[0], 0x60);
        assert_eq!(statusword(&d), sw, "after {cw:#06x}");
    }
    // Refused: switch on from switch on disabled.
    write(&mut d, 0x6040, 0, &0x07u16.to_le_bytes());
    assert_eq!(statusword(&d), 0x0540);
    // The mode display follows the mode.
    write(&mut d, 0x6060, 0, &[0x03]);
    assert_eq!(d.objects().value(cia402::MODES_OF_OPERATION_DISPLAY), Some(&[0x03][..]));
}

#[test]
fn a_fault_goes_through_fault_reaction_to_fault_and_resets_once_repaired() {
    let mut d = Device::new(super::super::profiles::drive(), Some(1), 2);
    d.on_frame(&Command::Start.frame(1));
    assert_eq!(statusword(&d), 0x0740, "remote while operational");
    for cw in [0x06u16, 0x07, 0x0F] {
        let out = d.on_frame(&Frame::new(0x601, &[0x2B, 0x40, 0x60, 0, cw as u8, 0, 0, 0]));
        // The SDO answer, then TPDO1 (event-driven, statusword) with the new state.
        assert_eq!(out.len(), 2, "{out:?}");
        assert_eq!(out[1], Frame::new(0x181, &statusword(&d).to_le_bytes()));
    }
    let now = 1_000_000;
    d.set_clock(now);
    write(&mut d, 0x5FFE, 0, &1u16.to_le_bytes());
    let frames = |out: Vec<(u64, Frame)>| out.into_iter().map(|(_, f)| f).collect::<Vec<_>>();
    let out = frames(d.events(now, now + 5));
    // EMCY 0x3220, register 0x05, then the statusword in fault reaction.
    assert_eq!(out[0], Frame::new(0x81, &[0x20, 0x32, 0x05, 0, 0, 0, 0, 0]));
    assert_eq!(out[1], Frame::new(0x181, &0x070Fu16.to_le_bytes()));
    let out = frames(d.events(now + 5, now + 5 + FAULT_REACTION_MS));
    assert_eq!(out.last(), Some(&Frame::new(0x181, &0x0708u16.to_le_bytes())));
    assert_eq!(d.objects().value(ObjAddr::new(0x1003, 0)), Some(&[1][..]));
    assert_eq!(d.objects().value(ObjAddr::new(0x1003, 1)), Some(&0x3220u32.to_le_bytes()[..]));
    // The cause is still there: no way out.
    write(&mut d, 0x6040, 0, &0x80u16.to_le_bytes());
    assert_eq!(statusword(&d), 0x0708);
    // Repaired: the fault stays latched until a reset edge, which reports "no error".
    write(&mut d, 0x5FFE, 0, &0u16.to_le_bytes());
    assert_eq!(statusword(&d), 0x0708);
    write(&mut d, 0x6040, 0, &0u16.to_le_bytes());
    let out = d.on_frame(&Frame::new(0x601, &[0x2B, 0x40, 0x60, 0, 0x80, 0, 0, 0]));
    assert_eq!(statusword(&d), 0x0740);
    assert!(out.contains(&Frame::new(0x81, &[0; 8])), "{out:?}");
    assert_eq!(d.objects().value(ObjAddr::new(0x1001, 0)), Some(&[0][..]));
}
