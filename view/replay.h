#pragma once
// --replay FILE: a recording (hail/recording.h) turned into Frames. Speeds come from the frames'
// velocities when the recording has them, else from the distance to the previous frame over
// the time between them.

#include <string>

#include "hail/recording.h"
#include "view/frame.h"

namespace hail::view {

class Replay {
 public:
  explicit Replay(const std::string& path) : reader_(RecordingReader::open_file(path)) {}

  [[nodiscard]] const RecordingHeader& header() const { return reader_.header(); }
  [[nodiscard]] std::size_t frame_count() const { return reader_.frame_count(); }
  /// Frame k (< frame_count()) into `out`. Throws InvalidArgument for a corrupt frame.
  void load(std::size_t k, Frame& out);

 private:
  RecordingReader reader_;
  RecordingFrame frame_, previous_;  // reused
};

}  // namespace hail::view
