#![no_main]
// Bytes from a serial port: both framings must decode or fail, never panic.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = canctl::epos2::frame::usb_decode(data);
    let _ = canctl::epos2::frame::rs232_decode(data);
    let mut d = canctl::epos2::frame::UsbDecoder::new();
    for b in data {
        if let Some(Ok(f)) = d.push(*b) {
            let _ = canctl::epos2::command::Command::from_frame(&f);
            let _ = canctl::epos2::command::parse_answer(&f);
        }
    }
});
