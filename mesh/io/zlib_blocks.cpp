#include "mesh/io/zlib_blocks.hpp"

#include <cstring>
#include <stdexcept>
#include <vector>

#include <tbb/parallel_for.h>
#include <zlib.h>

namespace tetfsi::mesh::io {

namespace {

// One zlib stream (header, deflate data, Adler-32) of `size` bytes, as compress2 makes, with the
// given strategy.
std::string deflate_block(const unsigned char* data, std::size_t size, int level, int strategy) {
  z_stream z{};
  if (deflateInit2(&z, level, Z_DEFLATED, 15, 8, strategy) != Z_OK) throw std::runtime_error("zlib deflateInit2 failed");
  std::string out(deflateBound(&z, static_cast<uLong>(size)), '\0');
  z.next_in = const_cast<Bytef*>(data);
  z.avail_in = static_cast<uInt>(size);
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (rc != Z_STREAM_END) throw std::runtime_error("zlib deflate failed");
  return out;
}

}  // namespace

void append_zlib_blocks(const unsigned char* data, std::size_t n, std::string& out, ZlibStrategy strategy,
                        int level, std::size_t block_size) {
  const std::size_t full = n / block_size, last = n % block_size;
  const std::size_t nb = full + (last ? 1 : 0);
  const int z_strategy = strategy == ZlibStrategy::Default ? Z_DEFAULT_STRATEGY : Z_RLE;
  auto size_of = [&](std::size_t b) { return b < full ? block_size : last; };
  std::vector<std::string> blocks(nb);
  std::size_t first = 0;  // blocks compressed before the others (the probe of RleOrStored)
  if (strategy == ZlibStrategy::RleOrStored && nb > 1) {
    blocks[0] = deflate_block(data, size_of(0), level, z_strategy);
    first = 1;
    if (static_cast<double>(blocks[0].size()) > (1.0 - kStoreBelowSaving) * static_cast<double>(size_of(0)))
      level = 0;  // the bytes do not compress: store the other blocks
  }
  tbb::parallel_for(first, nb, [&](std::size_t b) {
    blocks[b] = deflate_block(data + b * block_size, size_of(b), level, z_strategy);
  });
  std::vector<std::uint64_t> header = {nb, block_size, last};
  for (const auto& b : blocks) header.push_back(b.size());
  out.append(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t));
  for (const auto& b : blocks) out += b;
}

bool inflate_zlib_block(const unsigned char* compressed, std::size_t compressed_size, unsigned char* out,
                        std::size_t size) {
  uLongf got = static_cast<uLongf>(size);
  const int rc = uncompress(out, &got, compressed, static_cast<uLong>(compressed_size));
  return rc == Z_OK && got == size;
}

}  // namespace tetfsi::mesh::io
