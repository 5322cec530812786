// The CSV log and the checkpoints of a run directory (run_files.h).
//
// Checkpoint layout, little-endian whatever the host:
//   "VKTGCKPT"  u32 version
//   u64 iteration, f64 seconds, u64 optimizer steps, f64 adjoint scale
//   u64 counts: parameters K, first moments, second moments, bvhTheta, initial losses
//   K names as (u32 length, bytes); then the five double arrays in that order
//   u64 FNV-1a hash of every byte before it
// The counts are checked against the bytes left before anything is allocated, and the hash
// catches a garbled byte that a size check cannot see.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "io/io_internal.h"
#include "opt/run_files.h"
#include "scene/scene_values.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'V', 'K', 'T', 'G', 'C', 'K', 'P', 'T'};
constexpr uint32_t kCheckpointVersion = 2;
constexpr size_t kHeaderBytes = sizeof kMagic + 4;
constexpr size_t kHashBytes = 8;

uint64_t fnv1a(const char* data, size_t size) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (size_t i = 0; i < size; ++i) {
    hash ^= uint8_t(data[i]);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

uint64_t littleEndian64(const char* bytes) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t(uint8_t(bytes[i])) << (8 * i);
  return v;
}

class ByteWriter {
 public:
  void bytes(const void* data, size_t size) { m_out.append(static_cast<const char*>(data), size); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) m_out.push_back(char(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) m_out.push_back(char(v >> (8 * i)));
  }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void doubles(const std::vector<double>& values) {
    for (double v : values) f64(v);
  }
  std::string& text() { return m_out; }

 private:
  std::string m_out;
};

class ByteReader {
 public:
  ByteReader(const fs::path& path, const std::string& bytes, size_t end) : m_path(path), m_bytes(bytes), m_end(end) {}

  uint32_t u32() {
    const unsigned char* p = take(4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(p[i]) << (8 * i);
    return v;
  }
  uint64_t u64() { return littleEndian64(reinterpret_cast<const char*>(take(8))); }
  double f64() {
    const uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  std::string string() {
    const uint32_t length = u32();
    return std::string(reinterpret_cast<const char*>(take(length)), length);
  }
  // `count` doubles, checked against the bytes left before allocating.
  std::vector<double> doubles(uint64_t count, const char* what) {
    if (count > left() / 8) corrupt(std::string(what) + ": " + std::to_string(count) + " values do not fit in the file");
    std::vector<double> values(count);
    for (double& v : values) v = f64();
    return values;
  }
  void skip(size_t size) { take(size); }
  size_t left() const { return m_end - m_position; }
  [[noreturn]] void corrupt(const std::string& problem) const {
    fail(m_path.string(), "", "corrupt checkpoint: " + problem);
  }

 private:
  const unsigned char* take(uint64_t size) {
    if (size > left()) corrupt("truncated (a field runs past the end of the file)");
    const unsigned char* p = reinterpret_cast<const unsigned char*>(m_bytes.data()) + m_position;
    m_position += size;
    return p;
  }

  const fs::path& m_path;
  const std::string& m_bytes;
  size_t m_end;
  size_t m_position = 0;
};

// The sizes a checkpoint of K parameters may have: K first moments, 0 or K second moments (SGD or
// Adam), 0 or K BVH parameters (none built yet, or the θ it was built at).
std::string sizeProblem(uint64_t parameters, uint64_t names, uint64_t first, uint64_t second, uint64_t bvh) {
  auto text = [](uint64_t n) { return std::to_string(n); };
  if (names != parameters) return text(names) + " names for " + text(parameters) + " parameters";
  if (first != parameters) return text(first) + " first moments for " + text(parameters) + " parameters";
  if (second != 0 && second != parameters) return text(second) + " second moments for " + text(parameters) + " parameters";
  if (bvh != 0 && bvh != parameters) return text(bvh) + " BVH parameters for " + text(parameters) + " parameters";
  return "";
}

bool fitsCsvHeader(const std::string& name) {
  return !name.empty() && name.find_first_of(",\"\r\n") == std::string::npos;
}

std::string joined(const std::vector<std::string>& columns) {
  std::string line;
  for (const std::string& column : columns) line += (line.empty() ? "" : ",") + column;
  return line;
}

size_t fieldCount(const std::string& row) { return size_t(std::count(row.begin(), row.end(), ',')) + 1; }

}  // namespace

RunLog::RunLog(const fs::path& path, const std::vector<std::string>& columns, bool resume, uint64_t keepRows)
    : m_path(path), m_columns(columns.size()) {
  if (columns.empty()) fail(path.string(), "", "a log needs at least one column");
  for (const std::string& column : columns)
    if (!fitsCsvHeader(column)) fail(path.string(), "", "column name \"" + column + "\" cannot stand in a CSV header");
  const std::string header = joined(columns);
  if (!resume) {
    writeFileAtomic(path, header + "\n");
    return;
  }
  const std::string text = readTextFile(path);
  std::vector<std::string> lines;  // complete lines only: a last line without '\n' was cut short
  for (size_t begin = 0, end; (end = text.find('\n', begin)) != std::string::npos; begin = end + 1)
    lines.push_back(text.substr(begin, end - begin));
  if (lines.empty() || lines.front() != header)
    fail(path.string(), "", "header differs from this run's columns (expected \"" + header +
                                "\"): the log belongs to another experiment");
  const uint64_t rows = lines.size() - 1;
  if (rows < keepRows)
    fail(path.string(), "", "holds " + std::to_string(rows) + " complete rows, but the checkpoint the run resumes from "
                            "covers " + std::to_string(keepRows));
  std::string kept = header + "\n";
  for (uint64_t row = 1; row <= keepRows; ++row) {
    if (fieldCount(lines[row]) != m_columns)
      fail(path.string(), "line " + std::to_string(row + 1),
           "has " + std::to_string(fieldCount(lines[row])) + " fields, expected " + std::to_string(m_columns));
    kept += lines[row] + "\n";
  }
  writeFileAtomic(path, kept);
}

void RunLog::append(const std::vector<double>& values) {
  if (values.size() != m_columns)
    fail(m_path.string(), "", "a row of " + std::to_string(values.size()) + " values for " + std::to_string(m_columns) +
                                  " columns");
  std::string line;
  for (double value : values) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", value);
    if (!line.empty()) line += ',';
    line += text;
  }
  line += "\n";
  std::ofstream out(m_path, std::ios::binary | std::ios::app);
  out << line;
  out.flush();
  if (!out) fail(m_path.string(), "", "cannot append to the log: " + io::describeErrno(errno));
}

void writeCheckpoint(const fs::path& path, const Checkpoint& checkpoint) {
  const uint64_t count = checkpoint.theta.size();
  const std::string problem = sizeProblem(count, checkpoint.names.size(), checkpoint.optimizer.first.size(),
                                          checkpoint.optimizer.second.size(), checkpoint.bvhTheta.size());
  if (!problem.empty()) fail(path.string(), "", "cannot write an inconsistent checkpoint: " + problem);
  ByteWriter out;
  out.bytes(kMagic, sizeof kMagic);
  out.u32(kCheckpointVersion);
  out.u64(checkpoint.iteration);
  out.f64(checkpoint.seconds);
  out.u64(checkpoint.optimizer.steps);
  out.f64(checkpoint.adjointScale);
  for (size_t n : {checkpoint.theta.size(), checkpoint.optimizer.first.size(), checkpoint.optimizer.second.size(),
                   checkpoint.bvhTheta.size(), checkpoint.initialLoss.size()})
    out.u64(n);
  for (const std::string& name : checkpoint.names) {
    out.u32(uint32_t(name.size()));
    out.bytes(name.data(), name.size());
  }
  for (const std::vector<double>* values : {&checkpoint.theta, &checkpoint.optimizer.first, &checkpoint.optimizer.second,
                                            &checkpoint.bvhTheta, &checkpoint.initialLoss})
    out.doubles(*values);
  out.u64(fnv1a(out.text().data(), out.text().size()));
  writeFileAtomic(path, out.text());
}

Checkpoint readCheckpoint(const fs::path& path) {
  const std::string bytes = readTextFile(path);
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    fail(path.string(), "", "not a vktg checkpoint (no \"VKTGCKPT\" header)");
  if (bytes.size() < kHeaderBytes + kHashBytes) fail(path.string(), "", "corrupt checkpoint: truncated");
  ByteReader in(path, bytes, bytes.size() - kHashBytes);
  in.skip(sizeof kMagic);
  const uint32_t version = in.u32();
  if (version != kCheckpointVersion)
    fail(path.string(), "", "unsupported checkpoint version " + std::to_string(version) + " (this vktg reads version " +
                                std::to_string(kCheckpointVersion) + ")");
  if (littleEndian64(bytes.data() + bytes.size() - kHashBytes) != fnv1a(bytes.data(), bytes.size() - kHashBytes))
    in.corrupt("checksum mismatch (the file was truncated or changed after it was written)");

  Checkpoint checkpoint;
  checkpoint.iteration = in.u64();
  checkpoint.seconds = in.f64();
  checkpoint.optimizer.steps = in.u64();
  checkpoint.adjointScale = in.f64();
  const uint64_t count = in.u64(), first = in.u64(), second = in.u64(), bvh = in.u64(), losses = in.u64();
  const std::string problem = sizeProblem(count, count, first, second, bvh);
  if (!problem.empty()) in.corrupt("mismatched sizes: " + problem);
  // Each name takes at least its 4-byte length: a count beyond that cannot be genuine.
  if (count > in.left() / 4) in.corrupt(std::to_string(count) + " parameter names do not fit in the file");
  checkpoint.names.reserve(count);
  for (uint64_t i = 0; i < count; ++i) {
    checkpoint.names.push_back(in.string());
    if (!isValidParameterName(checkpoint.names.back()))
      in.corrupt("parameter " + std::to_string(i) + " has an invalid name");
  }
  checkpoint.theta = in.doubles(count, "theta");
  checkpoint.optimizer.first = in.doubles(first, "first moments");
  checkpoint.optimizer.second = in.doubles(second, "second moments");
  checkpoint.bvhTheta = in.doubles(bvh, "BVH parameters");
  checkpoint.initialLoss = in.doubles(losses, "initial losses");
  if (in.left() != 0) in.corrupt(std::to_string(in.left()) + " unexpected bytes after the last field");
  if (!(checkpoint.seconds >= 0) || !std::isfinite(checkpoint.seconds))
    in.corrupt("elapsed time " + std::to_string(checkpoint.seconds) + " s is not a finite, non-negative number");
  if (!(checkpoint.adjointScale >= 0) || !std::isfinite(checkpoint.adjointScale))
    in.corrupt("adjoint scale " + std::to_string(checkpoint.adjointScale) + " is not a finite, non-negative number");
  return checkpoint;
}

void checkCheckpointMatches(const fs::path& path, const Checkpoint& checkpoint, const Experiment& experiment) {
  const std::vector<ExperimentParameter>& parameters = experiment.parameters;
  if (checkpoint.names.size() != parameters.size())
    fail(path.string(), "", "written for " + std::to_string(checkpoint.names.size()) + " parameters, but the experiment "
                            "optimises " + std::to_string(parameters.size()));
  for (size_t i = 0; i < parameters.size(); ++i)
    if (checkpoint.names[i] != parameters[i].name)
      fail(path.string(), "", "written for other parameters: parameter " + std::to_string(i) + " is \"" +
                                  checkpoint.names[i] + "\" there and \"" + parameters[i].name + "\" in the experiment");
  // A run stopped before its first loss has none yet.
  const bool beforeFirstLoss = checkpoint.iteration == 0 && checkpoint.initialLoss.empty();
  if (checkpoint.initialLoss.size() != experiment.targets.size() && !beforeFirstLoss)
    fail(path.string(), "", "holds initial losses of " + std::to_string(checkpoint.initialLoss.size()) +
                                " targets, but the experiment has " + std::to_string(experiment.targets.size()));
}

}  // namespace vktg
