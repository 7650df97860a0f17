#include "log_bridge.hpp"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "vascsim/app/step_status.hpp"
#include "vascsim/experiments/run_assessment.hpp"

namespace vascsim::python {

namespace py = pybind11;

namespace {

struct LogLine {
  spdlog::level::level_enum level;
  std::string text;
};

// Queues the library's log lines until a thread with the GIL takes them (emit_log).
class QueueSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  std::vector<LogLine> take() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<LogLine> out = std::exchange(queue_, {});
    if (dropped_ > 0)
      out.push_back(
          {spdlog::level::warn, std::to_string(dropped_) + " log lines were dropped (the queue was full)"});
    dropped_ = 0;
    return out;
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    // Bounded: a long loop that does not return to Python (no callback) must not grow it without end.
    if (queue_.size() >= kMaxQueued) {
      ++dropped_;
      return;
    }
    queue_.push_back({msg.level, std::string(msg.payload.data(), msg.payload.size())});
  }
  void flush_() override {}

 private:
  static constexpr std::size_t kMaxQueued = 1000;
  std::vector<LogLine> queue_;
  std::size_t dropped_ = 0;
};

// Owned by spdlog's default logger too; holds no Python object, so its destruction at exit is safe.
std::shared_ptr<QueueSink>& queue_sink() {
  static std::shared_ptr<QueueSink> sink = std::make_shared<QueueSink>();
  return sink;
}

// A new reference held for the life of the process: the module keeps the type alive anyway.
PyObject* warning_category = nullptr;

int python_level(spdlog::level::level_enum level) {
  switch (level) {
    case spdlog::level::trace:
      return 5;
    case spdlog::level::debug:
      return 10;
    case spdlog::level::info:
      return 20;
    case spdlog::level::warn:
      return 30;
    case spdlog::level::err:
      return 40;
    default:
      return 50;
  }
}

py::object vascsim_logger() {
  return py::module_::import("logging").attr("getLogger")("vascsim");
}

}  // namespace

void bind_log(py::module_& m) {
  warning_category = PyErr_NewExceptionWithDoc(
      "vascsim.VascsimWarning",
      "What a run finds suspicious (the warnings the command line prints), issued through warnings.warn.",
      PyExc_UserWarning, nullptr);
  if (warning_category == nullptr) throw py::error_already_set();
  m.attr("VascsimWarning") = py::handle(warning_category);
  auto logger = std::make_shared<spdlog::logger>("vascsim", queue_sink());
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::info);
}

void warn(const std::string& text, int stacklevel) {
  py::module_::import("warnings").attr("warn")(text, py::handle(warning_category), stacklevel);
}

void emit_log(int stacklevel, std::set<std::string>* warned) {
  const std::vector<LogLine> lines = queue_sink()->take();
  if (lines.empty()) return;
  const py::object logger = vascsim_logger();
  for (const LogLine& l : lines) {
    if (l.level == spdlog::level::warn) {
      warn(l.text, stacklevel);
      if (warned) warned->insert(l.text);
    } else {
      logger.attr("log")(python_level(l.level), l.text);  // no arguments: a '%' in the text is not a format
    }
  }
}

void log_step(const std::string& label, const std::string& model, const StepRecord& record, int total) {
  const py::object logger = vascsim_logger();
  if (!logger.attr("isEnabledFor")(20).cast<bool>()) return;
  logger.attr("info")("%s: step %d of %d: %s (%.3g s)", label, record.step, total, step_status(model, record),
                      record.wall_s);
}

void log_accuracy_warnings(const Scene& scene, Simulation& sim) {
  if (const ForceAccuracyTable* table = bundled_force_accuracy())
    for (const std::string& w : model_accuracy_warnings(*table, scene, sim)) spdlog::warn("{}", w);
}

}  // namespace vascsim::python
