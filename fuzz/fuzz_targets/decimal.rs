//! The text form's exact parser of short decimals (`proto::text::parse_decimal`, what a
//! vertex line's numbers are read by) against `str::parse::<f64>` on arbitrary bytes:
//! where it reads a number, the bytes it took are one `str::parse` reads, to the same
//! bits; and it answers for every number of the shape a scene is written in. Run with
//! `-dict=dict/text.dict`.
#![no_main]
use libfuzzer_sys::fuzz_target;
use proto::text::parse_decimal;

fuzz_target!(|data: &[u8]| {
    if let Some((value, used)) = parse_decimal(data) {
        let word = std::str::from_utf8(&data[..used]).expect("a number is ASCII");
        let want = word.parse::<f64>().expect("str::parse reads what parse_decimal read");
        assert_eq!(value.to_bits(), want.to_bits(), "{word:?}");
    }
    // The bytes as a double's bits, printed as a scene prints it, then with the fuzzer's
    // bytes after it: always read here, to the bits.
    if let Some(bytes) = data.get(..8) {
        let x = f64::from_bits(u64::from_le_bytes(bytes.try_into().unwrap()));
        if x.is_finite() && (x == 0.0 || (1e-6..1e6).contains(&x.abs())) {
            let mut text = format!("{x}").into_bytes();
            let printed = text.len();
            text.push(b' ');
            text.extend_from_slice(&data[8..]);
            let read = parse_decimal(&text).map(|(v, used)| (v.to_bits(), used));
            assert_eq!(read, Some((x.to_bits(), printed)), "{x:?}");
        }
    }
});
