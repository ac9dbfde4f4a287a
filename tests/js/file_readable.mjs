// Shared by the JS checks: an @mcap/core IReadable over an open file handle, and sha256 in hex.
import { createHash } from "node:crypto";

export const sha256 = (bytes) => createHash("sha256").update(bytes).digest("hex");

/** IReadable over an open file handle, for McapIndexedReader. */
export class FileReadable {
  constructor(handle) {
    this.handle = handle;
  }
  async size() {
    return BigInt((await this.handle.stat()).size);
  }
  async read(offset, size) {
    const buffer = new Uint8Array(Number(size));
    for (let done = 0; done < buffer.length; ) {
      const position = Number(offset) + done;
      const { bytesRead } = await this.handle.read(buffer, done, buffer.length - done, position);
      if (bytesRead === 0) throw new Error(`unexpected end of file at byte ${position}`);
      done += bytesRead;
    }
    return buffer;
  }
}
