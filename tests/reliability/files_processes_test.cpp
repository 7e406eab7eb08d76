// Files and processes (issue #18): no shell for external tools, temporaries created exclusively
// (a planted symlink cannot redirect a write), leftovers of killed runs removed by the next run.
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "accuracy/pareto.h"
#include "cache/nph_cache.h"
#include "core/error.h"
#include "core/process.h"
#include "core/temp_files.h"
#include "reliability_support.h"
#include "scene/output_image.h"

namespace nph::reliability {
namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The pid of a process that has ended and been reaped (free, so "dead" to kill(pid, 0)).
pid_t deadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

/// Runs `fn` with the working directory set to `dir`.
void inDirectory(const fs::path& dir, const std::function<void()>& fn) {
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  fn();
  fs::current_path(before);
}

TEST(Processes, OutputPathCannotInjectAShellCommand) {
  // `nephele-bench accuracy -o "x';touch PWNED;'"` ran `touch PWNED` through std::system.
  const Scratch dir;
  const fs::path out = dir.path() / "x';touch PWNED;'";
  fs::create_directories(out);
  std::vector<accuracy::VariantSummary> summary(2);
  summary[0] = {"default", "", 10.0, 4.0, 6.0, 0.01, 0.001, 0.0, 0.001, 0.0, true};
  summary[1] = {"step", "0.5", 20.0, 8.0, 12.0, 0.005, 0.0005, 0.0, 0.0005, 0.0, true};
  bool plotted = false;
  inDirectory(dir.path(), [&] { plotted = accuracy::plotSummary(summary, (out / "accuracy").string()); });
  EXPECT_FALSE(fs::exists(dir.path() / "PWNED"));
  EXPECT_FALSE(fs::exists(out / "PWNED"));
  // gnuplot (Debian gnuplot-nox, in tools/debian-packages.txt) read the escaped paths and drew.
  EXPECT_TRUE(plotted);
  EXPECT_TRUE(fs::exists(out / "accuracy.png"));
}

TEST(Processes, GnuplotStringsAndPinnedToolPaths) {
  EXPECT_EQ(process::gnuplotQuoted("a'b"), "'a''b'");
  EXPECT_EQ(process::gnuplotQuoted("x\ny"), "'x y'");
  ::setenv("NEPHELE_FFMPEG", "ffmpeg", 1);  // not absolute: refused, PATH is not trusted for a pin
  expectError<UsageError>([] { (void)process::toolPath("NEPHELE_FFMPEG", "ffmpeg"); },
                          {"NEPHELE_FFMPEG", "expected the absolute path of an executable ffmpeg"});
  ::setenv("NEPHELE_FFMPEG", "/bin/sh", 1);
  EXPECT_EQ(process::toolPath("NEPHELE_FFMPEG", "ffmpeg"), "/bin/sh");
  ::unsetenv("NEPHELE_FFMPEG");
  EXPECT_EQ(process::toolPath("NEPHELE_FFMPEG", "ffmpeg"), "ffmpeg");
  EXPECT_EQ(process::run({"/bin/sh", "-c", "exit 3"}), 3);
  EXPECT_EQ(process::run({"/nonexistent/tool"}), 127);
}

TEST(Processes, ToolsAreSpawnedWithoutForkingThisProcess) {
  // A fork() of a multithreaded process (llvmpipe, plugin hosts) copies locks other threads hold
  // and runs every library's atfork handlers in the child: it deadlocked under ASan (issue #18).
  // posix_spawn runs no atfork handler, which the watch sees.
  const Scratch dir;
  const ForkWatch watch(dir);
  EXPECT_EQ(process::run({"true"}), 0);
  using How = process::Ending::How;
  const auto exited = process::runWithin({"/bin/sh", "-c", "exit 5"}, 60);
  ASSERT_TRUE(exited);
  EXPECT_EQ(exited->how, How::Exited);
  EXPECT_EQ(exited->code, 5);
  const auto killed = process::runWithin({"/bin/sh", "-c", "kill -TERM $$"}, 60);
  ASSERT_TRUE(killed);
  EXPECT_EQ(killed->how, How::Signalled);
  EXPECT_EQ(killed->code, SIGTERM);
  // A child that never ends on its own is killed at the limit (1 s); the outcome does not depend on
  // the machine's speed.
  const auto hung = process::runWithin({"/bin/sh", "-c", "exec sleep infinity"}, 1);
  ASSERT_TRUE(hung);
  EXPECT_EQ(hung->how, How::TimedOut);
  EXPECT_FALSE(process::runWithin({"/nonexistent/tool"}, 60));
  EXPECT_FALSE(watch.forked());
}

scene::RgbaImage grey(int w, int h) { return {w, h, std::vector<float>(std::size_t(w * h) * 4, 0.5f), {}}; }

TEST(TempFiles, PlantedSymlinkCannotRedirectAnImageWrite) {
  // The old temporary name was predictable (.frame.partial-<pid>-<n>.png) and opened with
  // O_CREAT|O_TRUNC: a symlink planted there made a render overwrite the link's target.
  const Scratch dir;
  const fs::path victim = dir.path() / "victim.txt";
  std::ofstream(victim) << "precious";
  for (int n = 0; n < 4; ++n) {
    fs::create_symlink(
        victim, dir.path() / (".frame.partial-" + std::to_string(::getpid()) + "-" + std::to_string(n) + ".png"));
  }
  scene::writeImage(grey(8, 4), (dir.path() / "frame.png").string());
  EXPECT_EQ(contents(victim), "precious");
  EXPECT_TRUE(fs::is_regular_file(dir.path() / "frame.png"));
  // The temporary is exclusive: creating one never reuses an existing name.
  const temp_files::Created a = temp_files::createExclusive(dir.path() / "f.png", ".f", ".partial-", ".png");
  const temp_files::Created b = temp_files::createExclusive(dir.path() / "f.png", ".f", ".partial-", ".png");
  EXPECT_NE(a.path, b.path);
  ::close(a.fd);
  ::close(b.fd);
}

TEST(TempFiles, LeftoversOfDeadProcessesAreRemovedByTheNextRun) {
  // A killed convert left NAME.tmp-XXXXXX, a killed render .NAME.partial-PID-N.*; reruns never
  // removed them. Temporaries of a live process (here: this one) must stay.
  const Scratch dir;
  const std::string dead = std::to_string(deadPid()), alive = std::to_string(::getpid());
  const fs::path stale_png = dir.path() / (".frame_000001.partial-" + dead + "-Ab12Cd.png");
  const fs::path stale_nph = dir.path() / ("storm.nph.tmp-" + dead + "-Xy34Zw");
  const fs::path live_png = dir.path() / (".frame_000002.partial-" + alive + "-Qw56Er.png");
  const fs::path unrelated = dir.path() / "notes.partial-draft.txt";
  for (const fs::path& p : {stale_png, stale_nph, live_png, unrelated}) std::ofstream(p) << "x";

  scene::writeImage(grey(4, 2), (dir.path() / "frame_000003.png").string());
  EXPECT_FALSE(fs::exists(stale_png));
  EXPECT_TRUE(fs::exists(live_png));
  EXPECT_TRUE(fs::exists(unrelated));
  EXPECT_TRUE(fs::exists(stale_nph));  // another marker: removed by the .nph writer

  const ExtinctionVolumes v = ExtinctionVolumes::zeros(4, 4, 2, 1000.0, 250.0, 0.0);
  cache::NphWriter w(dir.path() / "storm.nph", nphMetadataOf(v));
  EXPECT_FALSE(fs::exists(stale_nph));
  EXPECT_NE(w.temporaryPath().filename().string().find("storm.nph.tmp-" + alive + "-"), std::string::npos);
  w.append(v);
  w.commit();
  EXPECT_EQ(cache::NphReader(dir.path() / "storm.nph").timestepCount(), 1u);
}

TEST(TempFiles, SigtermRemovesTheTemporaryOfAConversion) {
  // A killed convert left NAME.tmp-XXXXXX behind. A child process stands in for the CLI: it
  // installs the handlers as main() does, starts a .nph, and is stopped by SIGTERM.
  const Scratch dir;
  const fs::path target = dir.path() / "storm.nph";
  const pid_t child = ::fork();
  if (child == 0) {
    temp_files::installSignalCleanup();
    cache::NphWriter w(target, nphMetadataOf(ExtinctionVolumes::zeros(4, 4, 2, 1000.0, 250.0, 0.0)));
    if (!fs::exists(w.temporaryPath())) ::_exit(2);
    ::raise(SIGTERM);
    ::_exit(3);  // not reached: the handler re-raises with the default action
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "child exit " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_TRUE(fs::is_empty(dir.path())) << "left: " << fs::directory_iterator(dir.path())->path();
}

TEST(TempFiles, FrameClaimsAreExclusiveAndTakenOverFromDeadProcesses) {
  // Two animate runs on one folder both rendered every frame; now each frame is claimed first.
  const Scratch dir;
  const fs::path path = dir.path() / ".frame_000001.claim";
  temp_files::Claim first, second;
  EXPECT_TRUE(first.tryAcquire(path));
  EXPECT_FALSE(second.tryAcquire(path));  // held by a live process (this one)
  EXPECT_EQ(second.holder(), ::getpid());
  first.release();
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(second.tryAcquire(path));
  second.release();
  // A killed run's claim is taken over.
  const pid_t dead = deadPid();
  std::ofstream(path) << dead;
  temp_files::Claim third;
  EXPECT_TRUE(third.tryAcquire(path));
  EXPECT_EQ(contents(path), std::to_string(::getpid()));
  third.release();
  // A symlink planted as the claim is neither followed nor removed.
  const fs::path victim = dir.path() / "victim.txt";
  std::ofstream(victim) << "precious";
  fs::create_symlink(victim, path);
  temp_files::Claim fourth;
  EXPECT_FALSE(fourth.tryAcquire(path));
  EXPECT_EQ(contents(victim), "precious");
}

}  // namespace
}  // namespace nph::reliability
