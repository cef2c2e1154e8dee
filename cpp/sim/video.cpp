#include "vwg/sim/video.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "vwg/error.hpp"
#include "vwg/sim/image_io.hpp"

extern char** environ;

namespace vwg::sim {

namespace {

namespace fs = std::filesystem;

std::string errno_text(int e) { return std::strerror(e); }

std::string size_text(cv::Size s) { return std::to_string(s.width) + "×" + std::to_string(s.height); }

/// A file descriptor closed when it goes out of scope.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  ~UniqueFd() { reset(); }
  UniqueFd(UniqueFd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) {
      reset();
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using UniqueFile = std::unique_ptr<std::FILE, FileCloser>;

/// posix_spawn's action and attribute objects must be destroyed on every path, including throws.
struct SpawnActions {
  posix_spawn_file_actions_t a;
  SpawnActions() { posix_spawn_file_actions_init(&a); }
  ~SpawnActions() { posix_spawn_file_actions_destroy(&a); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
};
struct SpawnAttr {
  posix_spawnattr_t a;
  SpawnAttr() { posix_spawnattr_init(&a); }
  ~SpawnAttr() { posix_spawnattr_destroy(&a); }
  SpawnAttr(const SpawnAttr&) = delete;
  SpawnAttr& operator=(const SpawnAttr&) = delete;
};

/// Writing to a pipe whose reader has exited raises SIGPIPE, which ends a C++ program (Python
/// ignores it, C++ does not). Blocked on this thread for the write, the failure comes back as EPIPE;
/// a SIGPIPE the write left pending is consumed before the mask is restored.
class SigpipeBlock {
 public:
  SigpipeBlock() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    sigset_t pending;
    sigemptyset(&pending);
    sigpending(&pending);
    was_pending_ = sigismember(&pending, SIGPIPE) == 1;
    pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
  }
  ~SigpipeBlock() {
    if (!was_pending_) {
      sigset_t pending;
      sigemptyset(&pending);
      sigpending(&pending);
      if (sigismember(&pending, SIGPIPE) == 1) {
        const timespec zero{0, 0};
        while (sigtimedwait(&pipe_, nullptr, &zero) < 0 && errno == EINTR) {
        }
      }
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeBlock(const SigpipeBlock&) = delete;
  SigpipeBlock& operator=(const SigpipeBlock&) = delete;

 private:
  sigset_t pipe_, old_;
  bool was_pending_ = false;
};

/// The program's path: `name` itself if it holds a '/', else the first executable on PATH.
std::optional<std::string> find_program(const std::string& name) {
  auto runnable = [](const std::string& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
  };
  if (name.empty()) return std::nullopt;
  if (name.find('/') != std::string::npos) return runnable(name) ? std::optional(name) : std::nullopt;
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/local/bin:/usr/bin:/bin";
  std::size_t from = 0;
  while (from <= path.size()) {
    const std::size_t colon = std::min(path.find(':', from), path.size());
    const std::string dir = colon > from ? path.substr(from, colon - from) : ".";
    const std::string candidate = dir + "/" + name;
    if (runnable(candidate)) return candidate;
    from = colon + 1;
  }
  return std::nullopt;
}

/// A child process fed through a pipe on its stdin; its stderr goes to an unnamed temporary file
/// (never a pipe nobody reads, which could fill up and stall it) that error messages quote.
/// Destroying it closes the pipe and waits, so an encoder left behind still finishes its file.
class PipedProcess {
 public:
  PipedProcess(const std::string& program, const std::vector<std::string>& args, const std::string& what) {
    int fds[2];
    // Close-on-exec, so encoders started later (another writer) do not inherit this pipe and keep
    // it open after we close our end.
    if (::pipe2(fds, O_CLOEXEC) != 0) throw Error(what + ": cannot create a pipe: " + errno_text(errno));
    UniqueFd read_end(fds[0]);
    stdin_ = UniqueFd(fds[1]);
#ifdef F_SETPIPE_SZ
    ::fcntl(stdin_.get(), F_SETPIPE_SZ, 1 << 20);  // fewer context switches per frame; a hint only
#endif
    log_.reset(std::tmpfile());
    if (!log_) throw Error(what + ": cannot create a temporary file for the encoder's messages: " + errno_text(errno));
    const int log_fd = ::fileno(log_.get());
    ::fcntl(log_fd, F_SETFD, FD_CLOEXEC);

    SpawnActions actions;
    posix_spawn_file_actions_adddup2(&actions.a, read_end.get(), 0);
    posix_spawn_file_actions_adddup2(&actions.a, log_fd, 2);
    posix_spawn_file_actions_addopen(&actions.a, 1, "/dev/null", O_WRONLY, 0);
    SpawnAttr attr;
    // Its own process group: Ctrl+C in a terminal interrupts the program, whose cleanup then
    // finishes the video, instead of also killing the encoder half-way.
    posix_spawnattr_setpgroup(&attr.a, 0);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGPIPE);
    sigaddset(&defaults, SIGINT);
    posix_spawnattr_setsigmask(&attr.a, &none);
    posix_spawnattr_setsigdefault(&attr.a, &defaults);
    posix_spawnattr_setflags(&attr.a, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);

    std::vector<std::string> storage;
    storage.reserve(args.size() + 1);
    storage.push_back(program);
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& s : storage) argv.push_back(s.data());
    argv.push_back(nullptr);
    const int rc = ::posix_spawn(&pid_, program.c_str(), &actions.a, &attr.a, argv.data(), environ);
    if (rc != 0) {
      pid_ = -1;
      throw Error(what + ": cannot start " + program + ": " + errno_text(rc));
    }
  }

  ~PipedProcess() {
    if (pid_ > 0 && !waited_) finish();
  }
  PipedProcess(const PipedProcess&) = delete;
  PipedProcess& operator=(const PipedProcess&) = delete;

  /// Write everything; 0 on success, else the errno (EPIPE: the process has exited).
  int write(const void* data, std::size_t n) {
    SigpipeBlock block;
    const auto* p = static_cast<const char*>(data);
    while (n > 0) {
      const ssize_t k = ::write(stdin_.get(), p, n);
      if (k < 0) {
        if (errno == EINTR) continue;
        return errno;
      }
      p += k;
      n -= static_cast<std::size_t>(k);
    }
    return 0;
  }

  /// Close its stdin (end of input) and wait for it. Returns its exit code, or 128 + the signal
  /// that killed it.
  int finish() {
    stdin_.reset();
    if (!waited_) {
      int status = 0;
      while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
      waited_ = true;
      status_ = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
    }
    return status_;
  }

  /// The last lines the process wrote to stderr, joined with "; ".
  std::string log_tail() const {
    std::string text;
    std::fflush(log_.get());
    std::rewind(log_.get());
    char buf[4096];
    std::size_t k;
    while ((k = std::fread(buf, 1, sizeof buf, log_.get())) > 0) text.append(buf, k);
    std::vector<std::string> lines;
    std::size_t from = 0;
    while (from < text.size()) {
      const std::size_t nl = std::min(text.find('\n', from), text.size());
      std::string line = text.substr(from, nl - from);
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
      if (!line.empty()) lines.push_back(line);
      from = nl + 1;
    }
    std::string out;
    for (std::size_t i = lines.size() > 4 ? lines.size() - 4 : 0; i < lines.size(); ++i) {
      out += (out.empty() ? "" : "; ") + lines[i];
    }
    return out.empty() ? "no message" : out;
  }

 private:
  pid_t pid_ = -1;
  UniqueFd stdin_;
  UniqueFile log_;
  bool waited_ = false;
  int status_ = -1;
};

enum class Format { Mp4, Gif };

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

struct VideoWriter::Impl {
  std::string path;
  cv::Size size;
  double fps = 0;
  VideoSettings settings;
  Format format = Format::Mp4;
  std::string ffmpeg;  // the resolved program; empty: OpenCV encodes
  std::int64_t frames = 0;
  std::string encoder;
  std::unique_ptr<PipedProcess> process;
  std::unique_ptr<cv::VideoWriter> cv_writer;
  cv::Mat bgr;  // OpenCV wants BGR frames; reused to avoid an allocation per frame

  void check_even(cv::Size s) const {
    if (format == Format::Mp4 && (s.width % 2 != 0 || s.height % 2 != 0)) {
      throw Error(path + ": H.264 in yuv420p (what browsers play) needs an even width and height, got " + size_text(s) +
                  " (RenderStyle::even_size gives even images)");
    }
  }

  void start() {
    if (ffmpeg.empty()) {
      cv_writer = std::make_unique<cv::VideoWriter>();
      bool ok = false;
      try {
        ok = cv_writer->open(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('a', 'v', 'c', '1'), fps, size, true);
      } catch (const cv::Exception& e) {
        throw Error(path + ": OpenCV cannot open an H.264 writer (" + e.msg + "); install the ffmpeg command");
      }
      if (!ok) throw Error(path + ": OpenCV cannot open an H.264 (avc1) writer; install the ffmpeg command");
      encoder = "opencv avc1";
      return;
    }
    std::vector<std::string> args{"-hide_banner", "-loglevel", "error", "-nostats", "-y",
                                  "-f", "rawvideo", "-pix_fmt", "rgb24", "-video_size",
                                  std::to_string(size.width) + "x" + std::to_string(size.height),
                                  "-framerate", number_text(fps), "-i", "pipe:0", "-an"};
    if (format == Format::Mp4) {
      // BT.709 conversion and tags: unconverted, swscale would use BT.601 while players assume
      // BT.709 for untagged video, and colours would shift. faststart puts the index first.
      args.insert(args.end(), {"-vf", "scale=out_color_matrix=bt709:out_range=tv,format=yuv420p",
                               "-c:v", "libx264", "-preset", settings.preset, "-crf", std::to_string(settings.crf),
                               "-pix_fmt", "yuv420p", "-color_primaries", "bt709", "-color_trc", "bt709",
                               "-colorspace", "bt709", "-color_range", "tv", "-movflags", "+faststart", "-f", "mp4"});
      encoder = "ffmpeg libx264";
    } else {
      // By default one palette per frame, made from that frame: streams (a global palette needs
      // every frame first, held in memory) and keeps flat colours exact. Browsers play delays
      // under 2/100 s slowly, so faster videos drop frames to 50 fps instead.
      std::string graph = fps > 50 ? "fps=50," : "";
      graph += settings.gif_global_palette
                   ? "split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse=diff_mode=rectangle:dither="
                   : "split[a][b];[a]palettegen=stats_mode=single[p];[b][p]paletteuse=new=1:dither=";
      graph += settings.gif_dither ? "bayer:bayer_scale=4" : "none";
      args.insert(args.end(), {"-vf", graph, "-loop", "0", "-f", "gif"});
      encoder = "ffmpeg gif";
    }
    // "file:" so a name with a colon is not taken for a protocol.
    args.push_back("file:" + fs::absolute(path).string());
    process = std::make_unique<PipedProcess>(ffmpeg, args, path);
  }

  /// Stop the encoder and check the result; `quiet_if_empty`: no error for a video without frames.
  void finish(bool quiet_if_empty) {
    std::string failure;
    if (process) {
      const int status = process->finish();
      if (status != 0 && frames > 0) {
        failure = "ffmpeg failed (exit status " + std::to_string(status) + ") after " + std::to_string(frames) +
                  " frames: " + process->log_tail();
      }
      process.reset();
    }
    if (cv_writer) {
      cv_writer->release();
      cv_writer.reset();
    }
    std::error_code ec;
    if (frames == 0) {
      fs::remove(path, ec);  // an empty or half-made container that no player opens
      if (!quiet_if_empty) throw Error(path + ": no frames were written; the file was removed");
      return;
    }
    if (!failure.empty()) throw Error(path + ": " + failure);
    const auto bytes = fs::file_size(path, ec);
    if (ec || bytes == 0) throw Error(path + ": the encoder (" + encoder + ") left no video behind");
  }
};

VideoWriter::VideoWriter() = default;

VideoWriter::VideoWriter(const std::string& path, int width, int height, double fps, VideoSettings settings) {
  open(path, width, height, fps, std::move(settings));
}

VideoWriter::~VideoWriter() {
  if (!impl_) return;
  try {
    impl_->finish(true);
  } catch (const std::exception& e) {
    // A destructor must not throw; the message is all that can be done for the caller.
    std::fprintf(stderr, "vwg: %s\n", e.what());
  }
}

VideoWriter::VideoWriter(VideoWriter&&) noexcept = default;

VideoWriter& VideoWriter::operator=(VideoWriter&& other) noexcept {
  if (this != &other) {
    VideoWriter old(std::move(*this));  // finishes the current video, as destruction does
    impl_ = std::move(other.impl_);
  }
  return *this;
}

void VideoWriter::open(const std::string& path, int width, int height, double fps, VideoSettings settings) {
  close();
  if (path.empty()) throw Error("VideoWriter: empty path");
  if (!(fps > 0) || !std::isfinite(fps)) throw Error(path + ": fps must be positive, got " + number_text(fps));
  if (width < 0 || height < 0 || (width == 0) != (height == 0)) {
    throw Error(path + ": bad frame size " + std::to_string(width) + "×" + std::to_string(height) +
                " (give both sides, or 0×0 to take the first frame's)");
  }
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->size = cv::Size(width, height);
  impl->fps = fps;
  impl->settings = std::move(settings);

  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".mp4" || ext == ".m4v") impl->format = Format::Mp4;
  else if (ext == ".gif") impl->format = Format::Gif;
  else throw Error(path + ": unknown video type '" + ext + "'; use .mp4 (H.264) or .gif");
  if (width > 0) impl->check_even(impl->size);

  const VideoBackend backend = impl->settings.backend;
  if (backend == VideoBackend::OpenCV) {
    if (impl->format == Format::Gif) throw Error(path + ": OpenCV cannot write GIF; use the ffmpeg backend");
  } else {
    const auto found = find_program(impl->settings.ffmpeg);
    if (found) impl->ffmpeg = *found;
    else if (backend == VideoBackend::Ffmpeg || impl->format == Format::Gif) {
      throw Error(path + ": the ffmpeg command ('" + impl->settings.ffmpeg + "') was not found on PATH; " +
                  (impl->format == Format::Gif ? "GIF needs it" : "it encodes H.264") +
                  " (Debian: apt-get install ffmpeg)");
    }
  }

  // Fail now, with the reason, rather than at the first frame or in the encoder's log.
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(path + ": is a folder, not a file");
  const fs::path folder = fs::absolute(path).parent_path();
  if (!fs::is_directory(folder, ec)) throw Error(path + ": cannot create the file: the folder " + folder.string() + " does not exist");
  {
    UniqueFd probe(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666));
    if (probe.get() < 0) throw Error(path + ": cannot create the file: " + errno_text(errno));
  }
  if (width > 0) {
    try {
      impl->start();
    } catch (...) {
      fs::remove(path, ec);  // the empty file the check above made
      throw;
    }
  }
  impl_ = std::move(impl);
}

void VideoWriter::write(const cv::Mat& rgb) {
  if (!impl_) throw Error("VideoWriter.write: no video is open");
  Impl& v = *impl_;
  const std::string which = v.path + ": frame " + std::to_string(v.frames);
  if (rgb.empty()) throw Error(which + " is empty");
  if (rgb.type() != CV_8UC3) {
    throw Error(which + " has " + std::to_string(rgb.channels()) + " channel(s) of " +
                std::to_string(rgb.elemSize1() * 8) + " bits; expected 8-bit RGB (CV_8UC3)");
  }
  if (v.size.width == 0) {
    v.check_even(rgb.size());
    v.size = rgb.size();
    try {
      v.start();
    } catch (...) {
      std::error_code ec;
      fs::remove(v.path, ec);  // the empty file open() made
      impl_.reset();           // no encoder: the writer is closed
      throw;
    }
  }
  if (rgb.size() != v.size) throw Error(which + " is " + size_text(rgb.size()) + ", the video is " + size_text(v.size));

  if (v.process) {
    int err = 0;
    if (rgb.isContinuous()) {
      err = v.process->write(rgb.data, rgb.total() * rgb.elemSize());
    } else {
      const std::size_t row = static_cast<std::size_t>(rgb.cols) * rgb.elemSize();
      for (int r = 0; r < rgb.rows && err == 0; ++r) err = v.process->write(rgb.ptr(r), row);
    }
    if (err != 0) {
      // The encoder is gone (bad disk, full disk, killed): report what it said, and stop.
      const int status = v.process->finish();
      const std::string log = v.process->log_tail();
      impl_.reset();
      throw Error(which + ": ffmpeg stopped (" + (err == EPIPE ? "exit status " + std::to_string(status) : errno_text(err)) +
                  "): " + log);
    }
  } else {
    cv::cvtColor(rgb, v.bgr, cv::COLOR_RGB2BGR);
    v.cv_writer->write(v.bgr);
  }
  ++v.frames;
}

void VideoWriter::close() {
  if (!impl_) return;
  std::unique_ptr<Impl> impl = std::move(impl_);  // closed even if finishing throws
  impl->finish(false);
}

bool VideoWriter::is_open() const { return impl_ != nullptr; }

const std::string& VideoWriter::path() const {
  static const std::string none;
  return impl_ ? impl_->path : none;
}

cv::Size VideoWriter::size() const { return impl_ ? impl_->size : cv::Size(); }
double VideoWriter::fps() const { return impl_ ? impl_->fps : 0.0; }
std::int64_t VideoWriter::frames() const { return impl_ ? impl_->frames : 0; }
std::string VideoWriter::encoder() const { return impl_ ? impl_->encoder : std::string(); }

// --- ImageSequence ---

ImageSequence::ImageSequence(std::string directory, std::string prefix, int first, int digits)
    : directory_(std::move(directory)), prefix_(std::move(prefix)), first_(first), digits_(digits) {
  if (directory_.empty()) directory_ = ".";
  if (first_ < 0) throw Error(directory_ + ": the first frame number must be >= 0");
  if (digits_ < 1 || digits_ > 12) throw Error(directory_ + ": digits must be 1..12");
  if (prefix_.find('/') != std::string::npos) throw Error(directory_ + ": the prefix must not hold a '/'");
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec || !fs::is_directory(directory_)) {
    throw Error(directory_ + ": cannot create the folder for the frames" + (ec ? ": " + ec.message() : std::string()));
  }
}

std::string ImageSequence::path_of(std::int64_t number) const {
  std::string n = std::to_string(number);
  if (n.size() < static_cast<std::size_t>(digits_)) n.insert(0, static_cast<std::size_t>(digits_) - n.size(), '0');
  return (fs::path(directory_) / (prefix_ + n + ".png")).string();
}

std::string ImageSequence::write(const cv::Mat& rgb) {
  const std::string path = path_of(first_ + count_);
  if (rgb.empty()) throw Error(path + ": the frame is empty");
  if (count_ == 0) {
    size_ = rgb.size();
    type_ = rgb.type();
  } else if (rgb.size() != size_ || rgb.type() != type_) {
    throw Error(path + ": the frame is " + size_text(rgb.size()) + " with " + std::to_string(rgb.channels()) +
                " channel(s); the sequence is " + size_text(size_) + " with " +
                std::to_string(CV_MAT_CN(type_)) + " (all frames must match the first)");
  }
  write_image(path, rgb);
  ++count_;
  return path;
}

}  // namespace vwg::sim
