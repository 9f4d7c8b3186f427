//! `hopnav launch --viewer ADDR`: a WebSocket client that speaks the Foxglove protocol sees
//! the channels advertised, subscribes to the robots' frames and decodes a message of a
//! running lockstep launch; a taken port or a bad address stops the launch before it starts.
//!
//! The `foxglove` crate's server (0.30) negotiates `foxglove.sdk.v1` (or `.v1.1`), the
//! renamed `foxglove.websocket.v1`: a client offering only the old name gets a 400. The
//! operations and the binary message frame are the same.

mod common;

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::sync::mpsc;
use std::time::Duration;

use common::*;
use foxglove::messages::FrameTransforms;
use prost::Message as _;
use tungstenite::client::ClientRequestBuilder;
use tungstenite::{Message, Utf8Bytes};

const SUBPROTOCOL: &str = "foxglove.sdk.v1";
/// The binary opcode of a message data frame.
const MESSAGE_DATA: u8 = 0x01;
const SUBSCRIPTION_ID: u32 = 7;

/// The `ws://` address the recorder announces on the launch's stderr.
fn announced_address(lines: &mpsc::Receiver<String>) -> String {
    loop {
        let line = lines
            .recv()
            .expect("the launch ended before announcing its viewer");
        if let Some((_, rest)) = line.split_once("viewer: ws://") {
            let address = rest.split_whitespace().next().expect("an address");
            return address.to_owned();
        }
    }
}

/// The id of the advertised channel of `topic`, from an `advertise` operation.
fn advertised_channel(text: &Utf8Bytes, topic: &str) -> Option<u64> {
    let json: serde_json::Value = serde_json::from_str(text.as_str()).ok()?;
    if json["op"] != "advertise" {
        return None;
    }
    json["channels"]
        .as_array()?
        .iter()
        .find(|channel| channel["topic"] == topic)
        .and_then(|channel| channel["id"].as_u64())
}

#[test]
fn a_foxglove_client_subscribes_and_decodes_the_robots_frames() {
    let out = out_dir("viewer");
    let run = run_id("viewer");
    // A mission that does not end at the goal: the launch runs until the test interrupts it.
    let config = out.join("endless.toml");
    std::fs::write(&config, "[mission]\nstop_on_goal = false\n").expect("config");
    let config = config.display().to_string();
    let args = [
        config.as_str(),
        "--lockstep",
        "--frames",
        "100000",
        "--viewer",
        "127.0.0.1:0",
    ];
    let mut launch = spawn_launch(&out, &run, &args);
    let stderr = launch.stderr.take().expect("stderr");
    let (sender, lines) = mpsc::channel();
    // Drain stderr to the end, so the launch never blocks on a full pipe.
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = sender.send(line);
        }
    });
    let address = announced_address(&lines);

    let stream = TcpStream::connect(&address).expect("connect to the viewer");
    // Only so that a broken server fails the test instead of hanging it.
    stream
        .set_read_timeout(Some(Duration::from_secs(120)))
        .expect("timeout");
    let uri = format!("ws://{address}").parse().expect("uri");
    let request = ClientRequestBuilder::new(uri).with_sub_protocol(SUBPROTOCOL);
    let (mut socket, response) = tungstenite::client(request, stream).expect("handshake");
    assert_eq!(
        response.headers()["sec-websocket-protocol"],
        SUBPROTOCOL,
        "{response:?}"
    );

    let mut subscribed = false;
    let transforms = loop {
        match socket.read().expect("a message from the viewer") {
            Message::Text(text) if !subscribed => {
                if let Some(channel_id) = advertised_channel(&text, "/foxglove/tf") {
                    let subscribe = serde_json::json!({
                        "op": "subscribe",
                        "subscriptions": [{ "id": SUBSCRIPTION_ID, "channelId": channel_id }],
                    });
                    socket
                        .send(Message::text(subscribe.to_string()))
                        .expect("subscribe");
                    subscribed = true;
                }
            }
            Message::Binary(frame) if frame.first() == Some(&MESSAGE_DATA) => {
                assert!(subscribed, "data before any subscription");
                let subscription = u32::from_le_bytes(frame[1..5].try_into().expect("id"));
                assert_eq!(subscription, SUBSCRIPTION_ID);
                let _log_time_ns = u64::from_le_bytes(frame[5..13].try_into().expect("time"));
                break FrameTransforms::decode(&frame[13..]).expect("a FrameTransforms");
            }
            _ => {}
        }
    };
    assert!(!transforms.transforms.is_empty());
    for transform in &transforms.transforms {
        assert_eq!(transform.parent_frame_id, "world");
        assert!(
            ["jumper_vo", "rover_vo", "jumper_truth", "rover_truth"]
                .contains(&transform.child_frame_id.as_str()),
            "{transform:?}"
        );
    }
    drop(socket);

    signal(launch.id() as i32, libc::SIGINT);
    let status = wait_with_limit(&mut launch, Duration::from_secs(120)).expect("launch stops");
    assert_eq!(status.code(), Some(130), "interrupted");
    reader.join().expect("stderr reader");
}

#[test]
fn a_taken_port_or_a_bad_address_is_refused_before_the_launch() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
    let address = taken.local_addr().expect("address").to_string();
    for (viewer, expected) in [
        (
            address.as_str(),
            format!("viewer cannot listen on {address}"),
        ),
        (
            "nowhere",
            "viewer address \"nowhere\" is not IP:PORT".to_owned(),
        ),
    ] {
        let out = out_dir("viewer-refused");
        let run = run_id("viewer-refused");
        let output = launch(
            &out,
            &run,
            &["--lockstep", "--frames", "3", "--viewer", viewer],
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(&expected), "{expected}: {stderr}");
        assert!(!out.join(&run).exists(), "nothing was started");
    }
}
