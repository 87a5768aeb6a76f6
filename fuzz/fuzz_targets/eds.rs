#![no_main]
// EDS/DCF files come from vendors and users: any bytes must give a dictionary or an error.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(eds) = canctl::od::eds::parse(data, "fuzz.eds") {
        // What was read must write and read back.
        let text = canctl::od::eds::write(&eds.dict, None, &Default::default());
        canctl::od::eds::parse(&canctl::od::eds::to_latin1(&text), "again.eds").expect("written EDS reads back");
    }
});
