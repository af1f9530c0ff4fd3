// libFuzzer target: the checkpoint reader of `tetfsi run --resume` (run::parse_checkpoint, then
// the runner state's reader, support/binary_stream.hpp, on the types runners store).
// First byte odd: the rest is the whole file (magic, version, scene hash, runner, payload length
// and hash). First byte even: the rest is the payload, behind a valid header with its FNV-1a hash,
// so that mutations reach the driver state and not only the hash check.
// Every input must end in a checkpoint or an InputError / BinaryReadError.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "apps/run/checkpoint.hpp"
#include "apps/run/errors.hpp"

namespace {
constexpr std::uint64_t kSceneHash = 0x1234567890abcdefull;
const std::string kRunner = "fuzz";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tetfsi;
  if (size < 1) return 0;
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  run::LoadedCheckpoint c;
  c.file = "fuzz/checkpoint_00001.bin";
  if (data[0] % 2 == 1) {
    c.bytes = rest;
  } else {
    BinaryWriter header;
    header.raw("TETFSICK", 8);
    header(run::kCheckpointVersion, kSceneHash, kRunner, std::uint64_t(rest.size()), run::fnv1a(rest));
    c.bytes = header.bytes() + rest;
  }
  try {
    run::parse_checkpoint(c, kSceneHash, kRunner);
    // The runner's state: the kinds of values the runners' state() members list.
    BinaryReader r = c.runner_state();
    std::vector<double> values;
    std::vector<bool> flags;
    std::vector<Eigen::Vector3d> points;
    Eigen::VectorXd vector;
    Eigen::MatrixXd matrix;
    Eigen::SparseMatrix<double> sparse;
    std::string text;
    double t = 0;
    r(t, values, flags, points, vector, matrix, sparse, text);
    r.expect_size(3, "the fuzz state");
  } catch (const run::InputError&) {
  } catch (const BinaryReadError&) {
  }
  return 0;
}
