// Writing rendered frames out: MP4 (H.264, yuv420p, faststart: what browsers play), GIF, or a
// folder of numbered PNG files. Frames are RGB (CV_8UC3), as the renderers draw them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace vwg::sim {

/// Which encoder a VideoWriter runs.
enum class VideoBackend {
  Auto,    ///< the ffmpeg command if it is found; else OpenCV for MP4 (GIF needs ffmpeg)
  Ffmpeg,  ///< frames piped to the ffmpeg command (libx264 / GIF palette filters)
  OpenCV,  ///< cv::VideoWriter, MP4 only: H.264 through OpenCV's FFmpeg, without faststart
};

/// Encoder settings; the defaults suit rendered maps (flat colours, thin lines).
struct VideoSettings {
  VideoBackend backend = VideoBackend::Auto;
  std::string ffmpeg = "ffmpeg";  ///< program name (looked up on PATH) or path
  int crf = 20;                   ///< H.264 quality: 0 lossless .. 51 worst; 18-23 look clean
  std::string preset = "fast";    ///< x264 speed against size: ultrafast .. veryslow
  bool gif_dither = false;        ///< GIF: dither (smoother fades) or not (crisper flat colours, smaller files)
  /// GIF: one palette for the whole video, ~4× faster and ~40% smaller, but ffmpeg then holds every
  /// frame in memory until close (~2 × width × height × 3 bytes a frame): for short clips only.
  /// Default: a palette per frame, streamed in bounded memory.
  bool gif_global_palette = false;
};

/// A video file being written, by extension: ".mp4" (H.264 High, yuv420p, BT.709, moov atom first so
/// browsers start playing before the download ends) or ".gif" (looping, a palette per frame unless
/// VideoSettings::gif_global_palette).
/// Destroying an open writer finishes the file as close() would (errors then go to stderr).
/// Not thread-safe: one thread writes a given video.
class VideoWriter {
 public:
  VideoWriter();  ///< closed; open() starts a video
  /// Opens at once; see open().
  VideoWriter(const std::string& path, int width, int height, double fps, VideoSettings settings = {});
  ~VideoWriter();  ///< finishes an open video
  VideoWriter(VideoWriter&&) noexcept;
  /// Finishes this writer's own open video first, as destruction would.
  VideoWriter& operator=(VideoWriter&&) noexcept;
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Start a video of width × height pixels (0 × 0: the size of the first frame) at `fps` frames
  /// per second, closing the one open before. Checks at once that the file can be created.
  /// Throws vwg::Error naming the file: unknown extension, folder missing or not writable, odd size
  /// for MP4 (yuv420p needs even sides), fps not positive, ffmpeg missing where it is needed.
  void open(const std::string& path, int width, int height, double fps, VideoSettings settings = {});
  /// Append one RGB frame (CV_8UC3) of the video's size. Throws vwg::Error naming the file and the
  /// frame on a wrong size or type, or when the encoder stopped (disk full, ...).
  void write(const cv::Mat& rgb);
  /// Finish the file and wait for the encoder. Throws vwg::Error if no frame was written (the file
  /// is then removed) or the encoder failed, with its last messages. Does nothing when not open.
  void close();

  /// Between open() and close() (or a failed write, which closes it).
  bool is_open() const;
  /// The file being written ("" when closed).
  const std::string& path() const;
  /// The frame size (0 × 0 until the first frame when opened without one).
  cv::Size size() const;
  double fps() const;           ///< frames per second of the open video
  std::int64_t frames() const;  ///< written so far
  /// What encodes: "ffmpeg libx264", "ffmpeg gif", "opencv avc1", or "" before the first frame.
  std::string encoder() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Frames as numbered PNG files in a folder: frame_00001.png, frame_00002.png, ... (an ffmpeg
/// image2 pattern `frame_%05d.png` reads them back). All frames must have the size of the first.
class ImageSequence {
 public:
  /// Creates the folder if needed. Throws vwg::Error naming it when it cannot.
  explicit ImageSequence(std::string directory, std::string prefix = "frame_", int first = 1, int digits = 5);
  /// Write the next frame (RGB, CV_8UC3; or grey / RGBA) and return the file's path.
  std::string write(const cv::Mat& rgb);
  /// The path frame number `number` has (number counts from `first`).
  std::string path_of(std::int64_t number) const;
  const std::string& directory() const { return directory_; }  ///< where the files go
  std::int64_t frames() const { return count_; }                ///< written so far

 private:
  std::string directory_, prefix_;
  int first_, digits_;
  std::int64_t count_ = 0;
  cv::Size size_;
  int type_ = -1;
};

}  // namespace vwg::sim
