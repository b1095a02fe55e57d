//! Fuzz target of the FX-style programming port: arbitrary bytes through the splitter
//! (in chunks chosen by the input), the request and reply decoders, the client state
//! machine (gutta_protocol::fx_client, reading them as answers) and the simulated device
//! (gutta_sim::fx). A request that decodes re-decodes the same from its encoding; the
//! client answers only ACK or data, retries the same bytes and gives up after exactly
//! 1 + retries misses; the device answers only ACK, NAK and well-formed data frames and
//! never writes its configuration block. A panic or a failed assertion is the bug it
//! looks for.
#![no_main]

use gutta_protocol::fx::{FxReply, FxRequest, FxSplitter, FxToken};
use gutta_protocol::fx_client::{FxClient, FxClientConfig, FxEvent};
use gutta_sim::fx::{factory_config, FxDevice};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&cut, stream)) = data.split_first() else {
        return;
    };
    let cut = usize::from(cut.max(1));
    let mut splitter = FxSplitter::new();
    let mut device = FxDevice::new();
    let config = FxClientConfig {
        timeout_ms: 10,
        retries: 2,
    };
    let mut client = FxClient::new(config);
    let request = FxRequest::Read {
        address: 0x0E02,
        len: 2,
    };
    let wire = request.encode().expect("the request encodes");
    let mut now = 0;
    assert_eq!(client.send(&request, now).as_ref(), Ok(&wire));
    for chunk in stream.chunks(cut) {
        now += 1 + u64::from(chunk[0] & 7);
        let event = if chunk[0] & 0x80 != 0 {
            client.on_tick(now)
        } else {
            client.on_bytes(chunk, now)
        };
        match event {
            FxEvent::Pending => {}
            FxEvent::Retry(bytes) => assert_eq!(bytes, wire),
            FxEvent::Reply(reply) => {
                assert!(reply != FxReply::Nak);
                assert_eq!(client.send(&request, now).as_ref(), Ok(&wire));
            }
            FxEvent::Failed(failure) => {
                assert_eq!(failure.misses.len(), 1 + config.retries as usize);
                assert_eq!(client.send(&request, now).as_ref(), Ok(&wire));
            }
            FxEvent::Idle => panic!("a request is outstanding"),
        }
        for token in splitter.push(chunk) {
            if let FxToken::Frame(frame) = &token {
                if let Ok(request) = FxRequest::decode(frame) {
                    let again = request.encode().expect("a decoded request encodes");
                    assert_eq!(FxRequest::decode(&again).as_ref(), Ok(&request));
                }
                if let Ok(reply) = FxReply::decode_data(frame) {
                    assert_eq!(FxReply::decode_data(&reply.encode()), Ok(reply));
                }
            }
        }
        let output = device.feed(chunk);
        let mut answers = FxSplitter::new();
        for token in answers.push(&output.reply) {
            assert!(FxReply::from_token(token).is_ok());
        }
        assert!(!answers.is_mid_frame() && answers.dropped == 0);
    }
    assert_eq!(device.memory()[0x8000..0x805C], factory_config()[..0x5C]);
});
