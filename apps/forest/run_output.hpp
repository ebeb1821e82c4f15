#pragma once
// What a multi-frame command leaves in its output folder: the files of one run only (an earlier
// run's files there are removed first), and a contact sheet sampled across the whole run.
#include <filesystem>
#include <string>
#include <vector>

#include "forest/core/image.hpp"

namespace forest::app {

// Removes what an earlier run of the same command left in `folder`: the named files and, with
// framesFolder, frames/frame*.png. Nothing else is touched (a folder of other files stays as it
// was). Returns how many files were removed.
int clearEarlierRun(const std::filesystem::path& folder, const std::vector<std::string>& ownedFiles, bool framesFolder);
// The same for what walkthrough, its window mode and budget write (they share --out folders):
// frames/frame*.png, report.json, contact-sheet.png, walkthrough.mp4, window.png. Logs what it removed.
int clearEarlierWalk(const std::filesystem::path& folder);

// Thumbnails sampled evenly across a run of unknown length (it may be interrupted): every
// stride-th frame is kept, and when more than 2·max are kept every other one goes and the stride
// doubles. compose() lays out up to `max` of them, spread from the first frame to the last one
// given, four per row, each labelled with its frame number, path time and frame time. Thumbnails are
// the frame shrunk by the smallest integer factor that fits thumbnailWidth (box filter).
class ContactSheet {
 public:
  explicit ContactSheet(int maxThumbnails = 16, int thumbnailWidth = 320);
  bool wants(int frame) const { return frame % stride_ == 0; }
  // Adds a frame (replacing an earlier entry of the same frame number).
  void add(int frame, double timeSeconds, double frameMs, const Image8& image);
  bool has(int frame) const;
  bool empty() const { return kept_.empty(); }
  // The frames compose() shows, in order.
  std::vector<int> shownFrames() const;
  Image8 compose() const;

 private:
  struct Thumbnail {
    int frame;
    double time;
    double frameMs;
    Image8 image;
  };
  int max_, width_, stride_ = 1;
  std::vector<Thumbnail> kept_;
  std::vector<size_t> shownIndices() const;
};

}  // namespace forest::app
