#pragma once
// Positional reads on a shared file descriptor: pread(2) takes the offset as an argument and
// leaves the descriptor's file position alone, so several threads may read one open file at once
// (FrameSource::load is called concurrently).
#include <cstddef>
#include <cstdint>

namespace rangecal {

/// Reads exactly n bytes at `offset` of `fd` into `buf`, retrying short reads and EINTR. False on
/// a read error or end of file before n bytes.
bool pread_all(int fd, void* buf, std::size_t n, std::uint64_t offset);

}  // namespace rangecal
