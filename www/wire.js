// A job's result on the wire (crates/web/src/jobs.rs): a u32 header length, the JSON header,
// padding to 8 bytes, the payload. Read by the worker, and by the page where it has no worker.
const arrays = { bytes: Uint8Array, f32: Float32Array, f64: Float64Array };

/** The result in `bytes`: `{ data, ...header }`, `data` a typed array of its own buffer. */
export const decode = (bytes) => {
  const length = new DataView(bytes.buffer, bytes.byteOffset).getUint32(0, true);
  const { payload, ...extra } = JSON.parse(new TextDecoder().decode(bytes.subarray(4, 4 + length)));
  const start = bytes.byteOffset + Math.ceil((4 + length) / 8) * 8;
  return { data: new arrays[payload](bytes.buffer.slice(start, bytes.byteOffset + bytes.byteLength)), ...extra };
};
