#pragma once
/// @file binary_stream.hpp
/// Little binary (de)serialization for checkpoints (apps/run/checkpoint.hpp): a writer that
/// appends values to a byte string and a reader whose every read is checked against the bytes
/// left, so that a truncated or corrupt file is an error (BinaryReadError), never a crash or a
/// silently wrong state. Values are stored in the machine's byte order (checkpoints are read back
/// by the same build on the same machine). Doubles are copied bit for bit, so a restored state is
/// the saved one exactly.
///
/// Each module serializes its own state next to its code with one member template that lists the
/// members once for both directions:
///
///     template <class Archive> void state(Archive& a) { a(x_, v_, time_); }
///
/// called with a BinaryWriter (save) or a BinaryReader (restore).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace tetfsi {

/// A checkpoint that is truncated or does not hold what its reader expects.
struct BinaryReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

namespace binary_detail {
/// Types copied as raw bytes: arithmetic types, enums and fixed-size Eigen matrices / std::arrays
/// of them (no padding inside).
template <class T, class = void>
struct is_raw : std::bool_constant<std::is_arithmetic_v<T> || std::is_enum_v<T>> {};
template <class T, std::size_t N>
struct is_raw<std::array<T, N>> : is_raw<T> {};
template <class S, int R, int C, int O, int MR, int MC>
struct is_raw<Eigen::Matrix<S, R, C, O, MR, MC>> : std::bool_constant<(R > 0 && C > 0 && std::is_arithmetic_v<S>)> {};
}  // namespace binary_detail

class BinaryWriter {
 public:
  const std::string& bytes() const { return bytes_; }
  std::string& bytes() { return bytes_; }

  template <class... T>
  void operator()(const T&... values) {
    (put(values), ...);
  }

  template <class T>
  std::enable_if_t<binary_detail::is_raw<T>::value> put(const T& v) {
    raw(&v, sizeof(T));
  }
  void put(bool v) { put(std::uint8_t(v ? 1 : 0)); }
  /// A struct: its `serialize(Archive&, T&)` found by argument-dependent lookup.
  template <class T>
  std::enable_if_t<!binary_detail::is_raw<T>::value && std::is_class_v<T>> put(const T& v) {
    serialize(*this, const_cast<T&>(v));
  }
  void put(const std::string& s) {
    put(std::uint64_t(s.size()));
    raw(s.data(), s.size());
  }
  template <class T>
  void put(const std::vector<T>& v) {
    put(std::uint64_t(v.size()));
    if constexpr (binary_detail::is_raw<T>::value && !std::is_same_v<T, bool>) {
      raw(v.data(), v.size() * sizeof(T));
    } else {
      for (const auto& x : v) put(x);
    }
  }
  void put(const std::vector<bool>& v) {
    put(std::uint64_t(v.size()));
    for (bool x : v) put(x);
  }
  template <class S, int O>
  void put(const Eigen::Matrix<S, Eigen::Dynamic, 1, O>& v) {
    put(std::uint64_t(v.size()));
    raw(v.data(), sizeof(S) * v.size());
  }
  template <class S>
  void put(const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& m) {
    (*this)(std::int64_t(m.rows()), std::int64_t(m.cols()));
    raw(m.data(), sizeof(S) * m.size());
  }
  /// A sparse matrix, compressed (as it is stored) with its exact pattern.
  void put(const Eigen::SparseMatrix<double>& m) {
    Eigen::SparseMatrix<double> c = m;
    c.makeCompressed();
    (*this)(std::int64_t(c.rows()), std::int64_t(c.cols()), std::int64_t(c.nonZeros()));
    raw(c.outerIndexPtr(), sizeof(int) * (c.outerSize() + 1));
    raw(c.innerIndexPtr(), sizeof(int) * c.nonZeros());
    raw(c.valuePtr(), sizeof(double) * c.nonZeros());
  }
  void raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }

 private:
  std::string bytes_;
};

class BinaryReader {
 public:
  /// Reads from `bytes` (kept by reference); `what` names the source in errors (a file path).
  BinaryReader(const std::string& bytes, std::string what)
      : BinaryReader(bytes.data(), bytes.size(), std::move(what)) {}
  /// Reads the `size` bytes at `data` (kept by pointer).
  BinaryReader(const char* data, std::size_t size, std::string what) : data_(data), size_(size), what_(std::move(what)) {}
  std::size_t left() const { return size_ - pos_; }
  /// The bytes not read yet.
  const char* here() const { return data_ + pos_; }
  /// Skips n bytes (checked).
  void skip(std::size_t n) {
    if (n > left()) fail("fewer bytes than its content needs");
    pos_ += n;
  }
  std::size_t position() const { return pos_; }

  template <class... T>
  void operator()(T&... values) {
    (get(values), ...);
  }

  template <class T>
  std::enable_if_t<binary_detail::is_raw<T>::value> get(T& v) {
    raw(&v, sizeof(T));
  }
  template <class T>
  std::enable_if_t<!binary_detail::is_raw<T>::value && std::is_class_v<T>> get(T& v) {
    serialize(*this, v);
  }
  void get(bool& v) {
    std::uint8_t b = 0;
    get(b);
    if (b > 1) fail("a flag that is neither 0 nor 1");
    v = b == 1;
  }
  void get(std::string& s) {
    const std::size_t n = count(1);
    s.assign(data_ + pos_, n);
    pos_ += n;
  }
  template <class T>
  void get(std::vector<T>& v) {
    if constexpr (binary_detail::is_raw<T>::value) {
      v.resize(count(sizeof(T)));
      raw(v.data(), v.size() * sizeof(T));
    } else {
      v.resize(count(1));
      for (auto& x : v) get(x);
    }
  }
  void get(std::vector<bool>& v) {
    v.resize(count(1));
    for (std::size_t i = 0; i < v.size(); ++i) {
      bool b = false;
      get(b);
      v[i] = b;
    }
  }
  template <class S, int O>
  void get(Eigen::Matrix<S, Eigen::Dynamic, 1, O>& v) {
    v.resize(static_cast<Eigen::Index>(count(sizeof(S))));
    raw(v.data(), sizeof(S) * v.size());
  }
  template <class S>
  void get(Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& m) {
    std::int64_t rows = 0, cols = 0;
    get(rows), get(cols);
    if (rows < 0 || cols < 0 || (rows > 0 && std::uint64_t(cols) > left() / sizeof(S) / std::uint64_t(rows)))
      fail("a matrix larger than the file");
    m.resize(rows, cols);
    raw(m.data(), sizeof(S) * m.size());
  }
  void get(Eigen::SparseMatrix<double>& m) {
    std::int64_t rows = 0, cols = 0, nnz = 0;
    get(rows), get(cols), get(nnz);
    if (rows < 0 || cols < 0 || nnz < 0 || std::uint64_t(nnz) > left() / 12 || std::uint64_t(cols) > left() / 4)
      fail("a sparse matrix larger than the file");
    m.resize(rows, cols);
    m.resizeNonZeros(nnz);
    raw(m.outerIndexPtr(), sizeof(int) * (cols + 1));
    raw(m.innerIndexPtr(), sizeof(int) * nnz);
    raw(m.valuePtr(), sizeof(double) * nnz);
    const int* outer = m.outerIndexPtr();
    if (outer[0] != 0 || outer[cols] != nnz) fail("a sparse matrix with a broken pattern");
    for (std::int64_t k = 0; k < cols; ++k)
      if (outer[k + 1] < outer[k]) fail("a sparse matrix with a broken pattern");
    for (std::int64_t k = 0; k < nnz; ++k)
      if (m.innerIndexPtr()[k] < 0 || m.innerIndexPtr()[k] >= rows) fail("a sparse matrix with a broken pattern");
  }
  void raw(void* p, std::size_t n) {
    if (n > left()) fail("fewer bytes than its content needs");
    if (n > 0) std::memcpy(p, data_ + pos_, n);
    pos_ += n;
  }
  /// A stored element count, checked against the bytes left at `bytes_each` bytes per element.
  std::size_t count(std::size_t bytes_each) {
    std::uint64_t n = 0;
    get(n);
    if (n > left() / (bytes_each ? bytes_each : 1)) fail("a length larger than the file");
    return static_cast<std::size_t>(n);
  }
  /// Throws BinaryReadError naming the source: "<what>: truncated or corrupt (<detail>)".
  [[noreturn]] void fail(const std::string& detail) const {
    throw BinaryReadError(what_ + ": truncated or corrupt checkpoint (" + detail + " at byte " + std::to_string(pos_) +
                          ")");
  }
  /// Reads a stored size and checks it equals `expected` (the size the set-up built).
  void expect_size(std::size_t expected, const char* what) {
    std::uint64_t n = 0;
    get(n);
    if (n != expected)
      fail(std::string(what) + ": " + std::to_string(n) + " stored, " + std::to_string(expected) + " in this run");
  }

 private:
  const char* data_;
  std::size_t size_;
  std::string what_;
  std::size_t pos_ = 0;
};

}  // namespace tetfsi
