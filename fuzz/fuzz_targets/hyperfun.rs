#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| bezsolid_fuzzing::hyperfun(data));
