#include "bench/bench_scale.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "bench/bench_common.h"
#include "optimize/optimize.h"
#include "vktg/error.h"
#include "vktg/image_io.h"

namespace vktg {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The processes' exchanges, timed: the accumulators' all-reduce (the largest integer sum of an
// iteration: the statistics' sums are a few numbers) and all of them.
class TimedCollective final : public Collective {
 public:
  explicit TimedCollective(Collective& inner) : m_inner(inner) {}
  int rank() const override { return m_inner.rank(); }
  int size() const override { return m_inner.size(); }
  void sumWrapping(std::span<uint64_t> values) override {
    const auto start = Clock::now();
    m_inner.sumWrapping(values);
    const double s = since(start);
    exchangeSeconds += s;
    if (values.size() > kStatistics) {
      allReduceSeconds += s;
      allReduceBytes = std::max<uint64_t>(allReduceBytes, values.size() * sizeof(uint64_t));
    }
  }
  void max(std::span<double> values) override { timed([&] { m_inner.max(values); }); }
  void broadcast(std::vector<uint8_t>& bytes) override { timed([&] { m_inner.broadcast(bytes); }); }
  std::vector<std::vector<uint8_t>> allGather(const std::vector<uint8_t>& bytes) override {
    std::vector<std::vector<uint8_t>> out;
    timed([&] { out = m_inner.allGather(bytes); });
    return out;
  }
  std::vector<std::vector<uint8_t>> gather(const std::vector<uint8_t>& bytes) override {
    std::vector<std::vector<uint8_t>> out;
    timed([&] { out = m_inner.gather(bytes); });
    return out;
  }
  void reset() { allReduceSeconds = exchangeSeconds = 0; }

  double allReduceSeconds = 0, exchangeSeconds = 0;
  uint64_t allReduceBytes = 0;

 private:
  static constexpr size_t kStatistics = 16;  // sumStats's counters, with room
  template <class F>
  void timed(F&& f) {
    const auto start = Clock::now();
    f();
    exchangeSeconds += since(start);
  }
  Collective& m_inner;
};

// The model's networks (docs/benchmarks.md states them): a ring all-reduce of B bytes over P
// processes takes 2 (P - 1) latency + 2 (P - 1) / P x B / bandwidth.
struct Network {
  const char* name;
  double latency;    // seconds per message
  double bandwidth;  // bytes per second, per process
};
constexpr Network kInNode = {"8 GPUs in one node, host-staged over PCIe 4.0 and shared memory", 5e-6, 10e9};
constexpr Network kNodes = {"one GPU per node, 100 Gb/s InfiniBand", 2e-6, 12.5e9};

double allReduceSeconds(const Network& net, int processes, double bytes) {
  if (processes <= 1) return 0;
  const double p = processes;
  return 2 * (p - 1) * net.latency + 2 * (p - 1) / p * bytes / net.bandwidth;
}

std::vector<BenchScaleRow> readRows(const std::filesystem::path& csv) {
  std::vector<BenchScaleRow> rows;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    BenchScaleRow r;
    unsigned long long targets = 0, parameters = 0, bytes = 0;
    if (std::sscanf(line.c_str(), "%d,%llu,%llu,%llu,%lf,%lf,%lf", &r.processes, &targets, &parameters, &bytes,
                    &r.iterationSeconds, &r.allReduceSeconds, &r.exchangeSeconds) != 7)
      throw Error(csv.string() + ": not a row of `vktg bench scale`: " + line);
    r.targets = targets;
    r.parameters = parameters;
    r.allReduceBytes = bytes;
    rows.push_back(r);
  }
  return rows;
}

std::string format(const char* pattern, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c, d);
  return text;
}

}  // namespace

BenchScaleRow benchScale(VulkanContext& context, const BenchScaleOptions& options) {
  std::optional<TimedCollective> timed;
  if (options.collective) timed.emplace(*options.collective);
  OptimizeOptions run;
  BenchScaleRow row;
  row.processes = options.collective ? options.collective->size() : 1;
  run.experiment = options.experiment;
  run.runDirectory = options.outDir / ("run-np" + std::to_string(row.processes));
  run.force = true;
  run.iterations = options.iterations + 1;
  run.memoryBudget = options.memoryBudget;
  run.collective = timed ? &*timed : nullptr;
  Optimization optimization(context, run);
  std::vector<double> seconds, reduce, exchange;
  for (uint32_t k = 0; !optimization.stopped(); ++k) {
    if (timed) timed->reset();
    const auto start = Clock::now();
    const Evaluation evaluation = optimization.evaluate();
    optimization.step(evaluation);
    row.targets = evaluation.targetLosses.size();
    if (k == 0) continue;  // pipelines, the first scale
    seconds.push_back(since(start));
    reduce.push_back(timed ? timed->allReduceSeconds : 0.0);
    exchange.push_back(timed ? timed->exchangeSeconds : 0.0);
  }
  optimization.finish();
  if (seconds.empty()) throw Error("bench scale: the experiment stopped before a timed iteration");
  row.parameters = optimization.parameterNames().size();
  row.allReduceBytes = timed ? timed->allReduceBytes : 0;
  row.iterationSeconds = median(seconds);
  row.allReduceSeconds = median(reduce);
  row.exchangeSeconds = median(exchange);
  return row;
}

void writeBenchScaleReport(const BenchScaleRow& row, const BenchScaleOptions& options, const std::string& command) {
  const std::filesystem::path csv = options.outDir / "scale.csv";
  std::vector<BenchScaleRow> rows = std::filesystem::exists(csv) ? readRows(csv) : std::vector<BenchScaleRow>{};
  std::erase_if(rows, [&](const BenchScaleRow& r) { return r.processes == row.processes; });
  rows.push_back(row);
  std::sort(rows.begin(), rows.end(), [](const BenchScaleRow& a, const BenchScaleRow& b) { return a.processes < b.processes; });
  std::ostringstream out;
  out << "processes,targets,parameters,allreduce_bytes,iteration_seconds,allreduce_seconds,exchange_seconds\n";
  for (const BenchScaleRow& r : rows)
    out << r.processes << "," << r.targets << "," << r.parameters << "," << r.allReduceBytes << ","
        << format("%.6f,%.6f,%.6f", r.iterationSeconds, r.allReduceSeconds, r.exchangeSeconds) << "\n";
  writeFileAtomic(csv, out.str());

  std::ostringstream md;
  md << "Measured (" << command << ", each row its own process count):\n\n"
     << "| processes | targets | parameters | s / iteration | all-reduce | its share | all exchanges | all-reduce bytes |\n"
     << "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const BenchScaleRow& r : rows)
    md << "| " << r.processes << " | " << r.targets << " | " << r.parameters << " | " << format("%.3f", r.iterationSeconds)
       << " | " << format("%.4f s", r.allReduceSeconds) << " | "
       << format("%.1f%%", 100 * r.allReduceSeconds / r.iterationSeconds) << " | " << format("%.4f s", r.exchangeSeconds)
       << " | " << r.allReduceBytes << " |\n";
  // The model: an iteration is a fixed cost (a render's and a gradient's passes, whatever the views
  // they hold) plus a cost per target of the process's share, plus the all-reduce. Both costs are
  // fitted to the rows' compute (an iteration less its exchanges) against their targets per
  // process; from one row, all of it is the targets'.
  double fixed = 0, perTarget = 0;
  {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const BenchScaleRow& r : rows) {
      const double x = double(r.targets) / r.processes, y = r.iterationSeconds - r.exchangeSeconds;
      n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double denominator = n * sxx - sx * sx;
    if (rows.size() > 1 && denominator > 0) perTarget = (n * sxy - sx * sy) / denominator;
    if (perTarget > 0) fixed = std::max(0.0, (sy - perTarget * sx) / n);
    else perTarget = sy / sx, fixed = 0;
  }
  md << "\nModel: t(P) = t_fixed + t_target x ceil(T / P) + a ring all-reduce of 8 bytes x K over P processes, fitted to\n"
     << "the rows above: t_fixed = " << format("%.4f s", fixed) << ", t_target = " << format("%.2e s", perTarget)
     << "; the second line of each scan, both 100 times smaller (a device 100 times faster).\n";
  struct Scan {
    const char* name;
    double targets, parameters;
  };
  const Scan scans[] = {{"10^4 parameters (100 x 100 heights), 64 x 64 scan", 4096, 1e4},
                        {"10^6 parameters (1000 x 1000 heights), 256 x 256 scan", 65536, 1e6}};
  for (const Network* net : {&kInNode, &kNodes}) {
    const std::vector<int> counts = net == &kInNode ? std::vector<int>{1, 2, 4, 8} : std::vector<int>{1, 8, 16, 64};
    md << "\n" << net->name << format(" (latency %.0f us, %.1f GB/s):\n\n", net->latency * 1e6, net->bandwidth / 1e9)
       << "| scan | t_target | P | all-reduce | strong: s / it | speed-up | weak: s / it | efficiency |\n"
       << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const Scan& scan : scans)
      for (const double faster : {1.0, 100.0}) {
        const double t = perTarget / faster, f = fixed / faster;
        const double bytes = 8 * scan.parameters;
        const double strong1 = f + t * scan.targets;
        // Weak: every process keeps the scan's targets of one process at P = 8 (or 64).
        const double perProcess = std::ceil(scan.targets / double(counts.back()));
        for (int p : counts) {
          const double reduce = allReduceSeconds(*net, p, bytes);
          const double strong = f + t * std::ceil(scan.targets / p) + reduce;
          const double weak = f + t * perProcess + reduce;
          md << "| " << scan.name << " | " << format("%.2e s", t) << " | " << p << " | " << format("%.2e s", reduce) << " | "
             << format("%.3g", strong) << " | " << format("%.2f", strong1 / strong) << " | " << format("%.3g", weak) << " | "
             << format("%.3f", (f + t * perProcess) / weak) << " |\n";
        }
      }
  }
  writeFileAtomic(options.outDir / "table.md", md.str());
  std::fputs(md.str().c_str(), stdout);
}

}  // namespace vktg
