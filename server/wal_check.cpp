#include "server/wal_check.h"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <vector>

namespace penumbra::server {

namespace {

// The WAL format (sqlite.org/fileformat2.html "WAL File Format"): a 32-byte header (magic,
// version, page size, checkpoint sequence, salt-1, salt-2, checksum-1, checksum-2), then frames of
// a 24-byte header (page number, size after commit, salt-1, salt-2, checksum-1, checksum-2) and one
// page. The checksum runs over 32-bit words in the byte order the magic names, cumulatively.
constexpr uint32_t kMagicLittle = 0x377f0682, kMagicBig = 0x377f0683;
constexpr size_t kHeader = 32, kFrameHeader = 24;

uint32_t bigEndian(const uint8_t* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

struct Checksum {
  uint32_t s0 = 0, s1 = 0;
  bool bigEndianWords = false;
  // SQLite's walChecksumBytes over `size` bytes (a multiple of 8).
  void add(const uint8_t* p, size_t size) {
    for (size_t i = 0; i + 8 <= size; i += 8) {
      const uint32_t x0 = bigEndianWords ? bigEndian(p + i)
                                         : uint32_t(p[i]) | uint32_t(p[i + 1]) << 8 |
                                               uint32_t(p[i + 2]) << 16 | uint32_t(p[i + 3]) << 24;
      const uint32_t x1 = bigEndianWords ? bigEndian(p + i + 4)
                                         : uint32_t(p[i + 4]) | uint32_t(p[i + 5]) << 8 |
                                               uint32_t(p[i + 6]) << 16 | uint32_t(p[i + 7]) << 24;
      s0 += x0 + s1;
      s1 += x1 + s0;
    }
  }
};

}  // namespace

std::string walProblem(const std::string& walPath) {
  std::ifstream in(walPath, std::ios::binary);
  if (!in) return "";
  const std::vector<uint8_t> wal((std::istreambuf_iterator<char>(in)),
                                 std::istreambuf_iterator<char>());
  if (wal.size() < kHeader) return "";
  const uint32_t magic = bigEndian(wal.data());
  const uint32_t pageSize = bigEndian(wal.data() + 8);
  if (magic != kMagicLittle && magic != kMagicBig) return "";  // not a log SQLite would replay
  if (pageSize < 512 || pageSize > 65536 || (pageSize & (pageSize - 1)) != 0)
    return "the write-ahead log's header is damaged (page size " + std::to_string(pageSize) + ")";
  Checksum sum;
  sum.bigEndianWords = magic == kMagicBig;
  sum.add(wal.data(), 24);
  // A header that fails its checksum makes SQLite ignore the whole log.
  const bool headerBroken =
      sum.s0 != bigEndian(wal.data() + 24) || sum.s1 != bigEndian(wal.data() + 28);
  const uint32_t salt1 = bigEndian(wal.data() + 16), salt2 = bigEndian(wal.data() + 20);
  const size_t frameSize = kFrameHeader + pageSize;
  size_t valid = 0, ignored = 0, lostCommits = 0;
  bool broken = headerBroken;
  for (size_t at = kHeader, frame = 1; at + frameSize <= wal.size(); at += frameSize, ++frame) {
    const uint8_t* header = wal.data() + at;
    const bool current = bigEndian(header + 8) == salt1 && bigEndian(header + 12) == salt2;
    if (broken) {  // written for this log after the break: SQLite ignores it
      ignored += current ? 1 : 0;
      lostCommits += current && bigEndian(header + 4) != 0 ? 1 : 0;  // a commit frame
      continue;
    }
    Checksum next = sum;
    next.add(header, 8);
    next.add(header + kFrameHeader, pageSize);
    if (!current || next.s0 != bigEndian(header + 16) || next.s1 != bigEndian(header + 20)) {
      broken = true;
      ignored += current ? 1 : 0;
      continue;
    }
    sum = next;
    valid = frame;
  }
  // A kill -9 can leave only the frame being written incomplete, at the end of an unacknowledged
  // transaction; a commit after the break means acknowledged transactions are lost.
  if (lostCommits == 0) return "";
  return "the write-ahead log is damaged after frame " + std::to_string(valid) +
         ": SQLite ignores " + std::to_string(ignored) + " later frame" +
         (ignored == 1 ? "" : "s") + " of it, " + std::to_string(lostCommits) +
         " committed transaction" + (lostCommits == 1 ? "" : "s") +
         " among them (acknowledged edits are missing)";
}

}  // namespace penumbra::server
