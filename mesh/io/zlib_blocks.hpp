#pragma once
/// @file zlib_blocks.hpp
/// The compressed-data layout of VTK XML files written with compressor="vtkZLibDataCompressor"
/// (docs.vtk.org "VTK XML file formats", section "Compressed data"; VTK's vtkXMLWriter and
/// vtkXMLDataParser). An array's bytes are cut into blocks of `block_size` bytes (the last one may
/// be shorter), each block is compressed on its own as a zlib stream (RFC 1950, zlib's compress2),
/// and the blocks are preceded by a header of 3 + nb words of the file's header_type:
///
///   [nb] [block_size] [size of the last block if partial, else 0] [compressed size of block 1..nb]
///
/// followed by the nb compressed blocks, back to back. The zlib library does the compression
/// (Debian zlib1g-dev).
#include <cstddef>
#include <cstdint>
#include <string>

namespace tetfsi::mesh::io {

/// Block size VTK uses (vtkXMLWriter::BlockSize) [bytes].
constexpr std::size_t kVtkBlockSize = 32768;

/// zlib level: 1 (fastest) .. 9 (smallest). On a flagship fluid frame (34,663 tets) level 6 is
/// 0.7% smaller than level 1 and 2.4 times slower: the mantissa bits of doubles do not compress
/// at any level.
constexpr int kVtuZlibLevel = 1;

/// How deflate looks for repeats. `Rle` (Z_RLE: matches at distance 1 only, i.e. runs, then
/// Huffman coding) suits floating-point arrays, whose values almost never repeat further back but
/// whose sign/exponent bytes and zero runs do: on the flagship fluid frame the float arrays come
/// out 1.4% larger than with the full search, in half the time. `Default` (full LZ77 search)
/// suits index arrays (connectivity 0.29 of its bytes vs 0.33 with Rle). `RleOrStored`: Rle,
/// except that an array whose first block shrinks by less than kStoreBelowSaving is written with
/// its other blocks stored (zlib level 0: the bytes inside a zlib stream, a copy instead of
/// Huffman coding): fields whose bytes are mantissa noise (on a flagship fluid frame: velocity,
/// smoke and pressure as Float32, 0.90-0.94 with Rle; the points) then cost a copy; fields with
/// runs or shared exponents (zeros, temperature near ambient: 0.71) are still compressed.
enum class ZlibStrategy { Default, Rle, RleOrStored };

/// RleOrStored stores an array's blocks after the first when the first one shrank by less than
/// this fraction.
constexpr double kStoreBelowSaving = 0.10;

/// Header (UInt64 words) + compressed blocks of `n` bytes at `data`, appended to `out`.
/// Blocks are compressed in parallel (TBB); the result does not depend on the thread count.
/// Each block is a standard zlib stream, whatever the strategy (any inflate reads it).
/// @throws std::runtime_error if zlib fails
void append_zlib_blocks(const unsigned char* data, std::size_t n, std::string& out,
                        ZlibStrategy strategy = ZlibStrategy::Default, int level = kVtuZlibLevel,
                        std::size_t block_size = kVtkBlockSize);

/// Inflates one zlib stream of `compressed_size` bytes into exactly `size` bytes at `out`.
/// @return false if the stream is corrupt or does not inflate to exactly `size` bytes
bool inflate_zlib_block(const unsigned char* compressed, std::size_t compressed_size, unsigned char* out,
                        std::size_t size);

}  // namespace tetfsi::mesh::io
