#![no_main]
// A device's 0x1021 is whatever it sends: any bytes, in either storage format, must unpack
// within the limit or be refused, never panic or run away with memory.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    for format in [canctl::od::stored::PLAIN, canctl::od::stored::ZIP] {
        if let Ok(file) = canctl::od::stored::unpack(format, data, 1 << 20) {
            assert!(file.len() <= (1 << 20).max(data.len()));
        }
    }
});
