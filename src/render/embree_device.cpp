#include "render/embree_device.h"

#include <atomic>
#include <mutex>

#include "core/cpu_isa.h"
#include "core/error.h"

namespace wheelpose::render {
namespace {

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "error";
}

// The first error Embree reported since the last check. Embree calls back on the thread that
// hit the error, which may be any TBB worker, and a C callback must not throw: it is stored and
// turned into an exception by throw_on_embree_error on the caller's thread.
struct PendingError {
  std::mutex mutex;
  std::atomic<bool> set{false};
  std::string message;
};

PendingError& pending() {
  static PendingError p;
  return p;
}

void on_embree_error(void* /*user*/, RTCError code, const char* text) {
  PendingError& p = pending();
  std::lock_guard lock(p.mutex);
  if (p.set.load()) return;
  p.message = std::string(error_name(code)) + (text && *text ? std::string(": ") + text : "");
  p.set.store(true);
}

RTCDevice create_device() {
  if (std::string problem = isa_problem(); !problem.empty()) throw Error(problem);
  const std::string config = embree_config_text();
  RTCDevice device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!device) {
    throw Error(
        "embree: cannot create a device" +
            (config.empty() ? std::string() : " with WHEELPOSE_EMBREE_CONFIG='" + config + "'") +
            " (" + error_name(rtcGetDeviceError(nullptr)) + ")",
        config.empty() ? ErrorKind::kFailure : ErrorKind::kBadInput);
  }
  rtcSetDeviceErrorFunction(device, on_embree_error, nullptr);
  return device;
}

}  // namespace

RTCDevice shared_embree_device() {
  // Not a function-local static initialised by a throwing lambda alone: a failed creation is
  // reported again, with the same message, on the next call.
  static std::mutex mutex;
  static RTCDevice device = nullptr;
  std::lock_guard lock(mutex);
  if (!device) device = create_device();
  return device;
}

void throw_on_embree_error(const std::string& during) {
  PendingError& p = pending();
  if (!p.set.load()) return;
  std::string message;
  {
    std::lock_guard lock(p.mutex);
    message = std::move(p.message);
    p.message.clear();
    p.set.store(false);
  }
  throw Error("embree: " + during + " failed: " + message, ErrorKind::kFailure);
}

}  // namespace wheelpose::render
