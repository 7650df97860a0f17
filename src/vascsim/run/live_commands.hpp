#pragma once
// The commands the viewer's UI thread sends to a live session's simulation thread (live_session.hpp), and
// their mailbox. The UI thread posts under a mutex (it may wait for microseconds); the simulation thread only
// try_locks it between frames, so it never waits for the UI: a command that finds the lock taken is picked
// up after the next frame.

#include <filesystem>
#include <mutex>
#include <optional>
#include <vector>

#include "vascsim/scene/scene.hpp"

namespace vascsim {

struct LiveCommand {
  enum class Kind {
    reset,            ///< rebuild the current scene from rest, with the interactive device
    load,             ///< rebuild with `scene` (another scene, model, material or solver settings)
    start_recording,  ///< rebuild from rest and record every haptic tick
    stop_recording,   ///< write the recording to `file`, keep running
    replay,           ///< rebuild from rest and play the recording `file` with a scripted device
    play_trajectory,  ///< rebuild from rest and play the scene's own scripted trajectory
  };
  Kind kind = Kind::reset;
  std::optional<Scene> scene;
  std::filesystem::path file;
};

class CommandMailbox {
 public:
  /// Any thread. Commands are taken in the order posted.
  void post(LiveCommand command) {
    const std::lock_guard lock(mutex_);
    pending_.push_back(std::move(command));
  }
  /// The simulation thread: the commands posted so far (empty if none, or if the lock is taken right now).
  std::vector<LiveCommand> take() {
    std::vector<LiveCommand> out;
    const std::unique_lock lock(mutex_, std::try_to_lock);
    if (lock.owns_lock()) out.swap(pending_);
    return out;
  }

 private:
  std::mutex mutex_;
  std::vector<LiveCommand> pending_;
};

}  // namespace vascsim
