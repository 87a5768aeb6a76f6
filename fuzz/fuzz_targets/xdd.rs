#![no_main]
// XDD/XDC files come from vendors and tools: any bytes must give a dictionary or an error
// with its position, and what was read must write as an XDC that reads back (or be refused
// with a reason).
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(eds) = canctl::od::xdd::parse(data, "fuzz.xdd") {
        if let Ok(bytes) = canctl::od::xdd::write_bytes(&eds.dict, None, &Default::default()) {
            canctl::od::xdd::parse(&bytes, "again.xdc").expect("written XDC reads back");
        }
    }
});
