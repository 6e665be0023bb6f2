// ROS 2 bags through an implementation that is not ours: Foxglove's @mcap/core and
// @foxglove/rosmsg2-serialization with the official message definitions
// (@foxglove/rosmsg-msgs-common), fetched by scripts/fetch-ros2-test-peers.sh. Run with
// NODE_PATH=data/npm-ros2/node_modules (tests/python/test_cli_ros2_peers.py does).
//
//   node peer_bags.cjs write FRAMES_DIR OUT.mcap   a rosbag2 MCAP of the frames FRAMES_DIR/frames.json lists
//   node peer_bags.cjs read BAG.mcap               every message decoded; a JSON summary on stdout
"use strict";
const fs = require("fs");
const path = require("path");
const { execFileSync } = require("child_process");
const { McapWriter, McapIndexedReader } = require("@mcap/core");
const { MessageReader, MessageWriter } = require("@foxglove/rosmsg2-serialization");
const { parse } = require("@foxglove/rosmsg");
const { ros2humble } = require("@foxglove/rosmsg-msgs-common");

const TYPES = { image: "sensor_msgs/msg/Image", info: "sensor_msgs/msg/CameraInfo", tf: "tf2_msgs/msg/TFMessage" };

const definitionsIn = require("./definitions.cjs");
const officialDefinitions = (rosType) => definitionsIn(ros2humble, rosType);

// The same .msg text rosbag2 stores in a schema (the root's fields, then each used type).
function msgText(rosType) {
  const defs = officialDefinitions(rosType);
  const fieldLine = (f) => {
    const type = f.type === "time" ? "builtin_interfaces/Time" : f.type;
    const array = f.isArray ? (f.arrayLength !== undefined ? `[${f.arrayLength}]` : "[]") : "";
    return `${type}${array} ${f.name}\n`;
  };
  let text = defs[0].definitions.map(fieldLine).join("");
  for (const d of defs.slice(1)) text += `${"=".repeat(80)}\nMSG: ${d.name}\n${d.definitions.map(fieldLine).join("")}`;
  return text;
}

// "1305031102.175304" -> { sec, nanosec } exactly (the TUM text stamps have six decimals).
function stampOf(text) {
  const [sec, frac = ""] = text.split(".");
  return { sec: Number(sec), nanosec: Number((frac + "000000000").slice(0, 9)) };
}
const nanoseconds = (s) => BigInt(s.sec) * 1000000000n + BigInt(s.nanosec);

async function writeBag(framesDir, outFile) {
  const spec = JSON.parse(fs.readFileSync(path.join(framesDir, "frames.json"), "utf8"));
  const chunks = [];
  const writable = { position: () => BigInt(chunks.reduce((n, c) => n + c.length, 0)), write: async (b) => { chunks.push(Buffer.from(b)); } };
  const writer = new McapWriter({ writable, useChunks: true, chunkSize: 1 << 20 });
  await writer.start({ profile: "ros2", library: "peer_bags.cjs (@mcap/core)" });
  const channels = {};
  const writers = {};
  for (const [key, type] of Object.entries(TYPES)) {
    const schemaId = await writer.registerSchema({ name: type, encoding: "ros2msg", data: new TextEncoder().encode(msgText(type)) });
    writers[key] = new MessageWriter(officialDefinitions(type));
    channels[key] = schemaId;
  }
  const channel = async (schemaId, topic) => writer.registerChannel({ schemaId, topic, messageEncoding: "cdr", metadata: new Map() });
  const rgb = await channel(channels.image, "/camera/rgb/image_color");
  const depth = await channel(channels.image, "/camera/depth/image");
  const info = await channel(channels.info, "/camera/rgb/camera_info");
  const tf = await channel(channels.tf, "/tf");
  let sequence = 0;
  const put = async (channelId, stamp, data) =>
    writer.addMessage({ channelId, sequence: sequence++, logTime: nanoseconds(stamp), publishTime: nanoseconds(stamp), data });
  const c = spec.camera;
  for (const f of spec.frames) {
    const ts = stampOf(f.rgb_stamp), td = stampOf(f.depth_stamp);
    const image = (stamp, frame_id, encoding, bytesPerPixel, file) => ({
      header: { stamp, frame_id }, height: c.height, width: c.width, encoding, is_bigendian: 0,
      step: c.width * bytesPerPixel, data: new Uint8Array(fs.readFileSync(path.join(framesDir, file))),
    });
    await put(rgb, ts, writers.image.writeMessage(image(ts, "/openni_rgb_optical_frame", "rgb8", 3, f.rgb)));
    await put(info, ts, writers.info.writeMessage({
      header: { stamp: ts, frame_id: "/openni_rgb_optical_frame" }, height: c.height, width: c.width,
      distortion_model: "plumb_bob", d: c.d, k: [c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1], r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
      p: [c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
      roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false },
    }));
    await put(depth, td, writers.image.writeMessage(image(td, "/openni_depth_optical_frame", "32FC1", 4, f.depth)));
  }
  for (const g of spec.groundtruth) {
    const stamp = stampOf(g.stamp);
    await put(tf, stamp, writers.tf.writeMessage({ transforms: [{
      header: { stamp, frame_id: "/world" }, child_frame_id: "/kinect",
      transform: { translation: { x: g.t[0], y: g.t[1], z: g.t[2] }, rotation: { x: g.q[0], y: g.q[1], z: g.q[2], w: g.q[3] } },
    }] }));
  }
  await writer.end();
  fs.writeFileSync(outFile, Buffer.concat(chunks));
}

// MCAP chunks our writer compresses with zstd (the default) or lz4: Node 20 has neither, the
// Debian command-line tools do.
const viaTool = (tool) => (data, size) => {
  const out = execFileSync(tool, ["-d", "-c", "-q"], { input: Buffer.from(data), maxBuffer: Number(size) + (1 << 20) });
  if (BigInt(out.length) !== size) throw new Error(`${tool}: ${out.length} bytes, the chunk says ${size}`);
  return new Uint8Array(out);
};

async function readBag(file) {
  const bytes = fs.readFileSync(file);
  const readable = { size: async () => BigInt(bytes.length), read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)) };
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers: { zstd: viaTool("zstd"), lz4: viaTool("lz4") } });
  const decoders = new Map();
  const summary = { profile: reader.header.profile, statistics: null, topics: {}, schemasMatchOfficial: true, chunkCompressions: [] };
  summary.statistics = { messageCount: Number(reader.statistics.messageCount), channelCount: reader.statistics.channelCount, chunkCount: reader.statistics.chunkCount };
  summary.chunkCompressions = [...new Set(reader.chunkIndexes.map((c) => c.compression))];
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    // Our schema text parsed by Foxglove's parser against the official definitions.
    const ours = parse(new TextDecoder().decode(schema.data), { ros2: true });
    const official = officialDefinitions(schema.name);
    const fieldsOf = (d) => JSON.stringify(d.definitions.map((f) => [f.name, f.type.split("/").pop(), !!f.isArray, f.arrayLength ?? null]));
    // The root, then every type the official definition uses, field for field (builtin_interfaces
    // types are primitives there).
    const byName = new Map(ours.slice(1).map((d) => [d.name, d]));
    const same = (o, i) => fieldsOf(i === 0 ? ours[0] : byName.get(o.name) ?? { definitions: [] }) === fieldsOf(o);
    if (!official.every(same)) summary.schemasMatchOfficial = false;
    decoders.set(id, new MessageReader(official));
    summary.topics[channel.topic] = { type: schema.name, encoding: channel.messageEncoding, schemaEncoding: schema.encoding, count: 0, frameIds: [], stamps: [], sizes: [], encodings: [], dataBytes: [] };
  }
  for await (const m of reader.readMessages()) {
    const channel = reader.channelsById.get(m.channelId);
    const t = summary.topics[channel.topic];
    const msg = decoders.get(m.channelId).readMessage(m.data);
    const header = msg.header ?? msg.transforms[0].header;
    t.count += 1;
    if (!t.frameIds.includes(header.frame_id)) t.frameIds.push(header.frame_id);
    t.stamps.push(`${header.stamp.sec}.${String(header.stamp.nanosec).padStart(9, "0")}`);
    if (nanoseconds(header.stamp) !== m.logTime) throw new Error(`${channel.topic}: log time ${m.logTime} is not the header stamp`);
    if (msg.width !== undefined) t.sizes.push([msg.width, msg.height]);
    if (msg.encoding !== undefined) { t.encodings.push(msg.encoding); t.dataBytes.push(msg.data.length); }
    if (msg.k !== undefined) t.camera = { k: Array.from(msg.k), d: Array.from(msg.d), distortion_model: msg.distortion_model };
    if (msg.transforms !== undefined) t.childFrameIds = [...new Set([...(t.childFrameIds ?? []), ...msg.transforms.map((x) => x.child_frame_id)])];
  }
  process.stdout.write(JSON.stringify(summary));
}

const [command, ...args] = process.argv.slice(2);
const run = command === "write" ? writeBag(args[0], args[1]) : command === "read" ? readBag(args[0]) : Promise.reject(new Error(`usage: peer_bags.cjs write DIR OUT.mcap | read BAG.mcap`));
run.catch((e) => { process.stderr.write(`peer_bags: ${e.stack ?? e}\n`); process.exit(1); });
