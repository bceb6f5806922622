// Devices of the Barthel-test agents: real espeak-ng speech, OpenCV screen, JSON result store,
// file pager, their simulated twins, and the Barthel items.

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "quiver/agents/devices/espeak_speech_output.h"
#include "quiver/agents/devices/file_pager.h"
#include "quiver/agents/devices/json_result_store.h"
#include "quiver/agents/devices/memory_pager.h"
#include "quiver/agents/devices/memory_result_store.h"
#include "quiver/agents/devices/opencv_screen.h"
#include "quiver/agents/devices/simulated_screen.h"
#include "quiver/agents/devices/simulated_speech_output.h"
#include "quiver/agents/devices/test_result_json.h"
#include "quiver/agents/devices/wav_info.h"

namespace quiver::agents::devices {
namespace {

namespace fs = std::filesystem;
constexpr std::int64_t kSecond = 1'000'000'000;

// A fresh directory per test, removed afterwards.
class DevicesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("quiver_devices_" + std::to_string(::getpid()) + "_" +
                                        info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// ---- WAV files built by hand -------------------------------------------------------------

std::string le16(std::uint16_t v) { return {static_cast<char>(v & 0xff), static_cast<char>(v >> 8)}; }
std::string le32(std::uint32_t v) {
  return {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
          static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
}
std::string chunk(const std::string& id, const std::string& body) {
  std::string c = id + le32(static_cast<std::uint32_t>(body.size())) + body;
  if (body.size() % 2 == 1) c += '\0';
  return c;
}
std::string fmt_chunk(std::uint16_t tag, std::uint16_t channels, std::uint32_t rate,
                      std::uint16_t bits) {
  const std::uint16_t align = static_cast<std::uint16_t>(channels * ((bits + 7) / 8));
  return chunk("fmt ", le16(tag) + le16(channels) + le32(rate) + le32(rate * align) +
                           le16(align) + le16(bits));
}
std::string riff(const std::string& chunks) {
  return "RIFF" + le32(static_cast<std::uint32_t>(4 + chunks.size())) + "WAVE" + chunks;
}

TEST_F(DevicesTest, WavChunksInAnyOrder) {
  // 16 kHz stereo 16-bit: 64,000 bytes per second. data before fmt, an odd-sized LIST between.
  const std::string wav = riff(chunk("data", std::string(96'000, '\x01')) +
                               chunk("LIST", std::string(7, 'x')) + fmt_chunk(1, 2, 16000, 16));
  write_all(path("odd.wav"), wav);
  Result<WavInfo> info = read_wav_info(path("odd.wav"));
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->channels, 2);
  EXPECT_EQ(info->sample_rate, 16000u);
  EXPECT_EQ(info->bits_per_sample, 16);
  EXPECT_EQ(info->data_bytes, 96'000u);
  EXPECT_EQ(info->duration_ns, 1'500'000'000);

  // 8 kHz mono 8-bit float-free PCM, with the fmt chunk extended to 18 bytes.
  std::string fmt18 = fmt_chunk(1, 1, 8000, 8);
  fmt18 = "fmt " + le32(18) + fmt18.substr(8) + le16(0);
  write_all(path("ext.wav"), riff(fmt18 + chunk("data", std::string(2000, '\x02'))));
  Result<WavInfo> ext = read_wav_info(path("ext.wav"));
  ASSERT_TRUE(ext.ok()) << ext.error().to_string();
  EXPECT_EQ(ext->duration_ns, 250'000'000);
}

TEST_F(DevicesTest, MalformedWavsAreErrorsNamingTheFile) {
  struct Case {
    std::string name;
    std::string bytes;
    ErrorCode code;
    std::string says;
  };
  const std::string good_fmt = fmt_chunk(1, 1, 22050, 16);
  const std::vector<Case> cases = {
      {"empty.wav", "", ErrorCode::kTruncated, "shorter than a RIFF/WAVE header"},
      {"text.wav", "this is not a wave file at all", ErrorCode::kMalformed, "RIFF"},
      {"avi.wav", "RIFF" + le32(4) + "AVI ", ErrorCode::kMalformed, "not 'WAVE'"},
      {"nofmt.wav", riff(chunk("data", std::string(100, '\0'))), ErrorCode::kMalformed,
       "no 'fmt ' chunk"},
      {"nodata.wav", riff(good_fmt), ErrorCode::kMalformed, "no 'data' chunk"},
      {"shortfmt.wav", riff(chunk("fmt ", std::string(10, '\0')) + chunk("data", "ab")),
       ErrorCode::kMalformed, "fewer than 16"},
      {"zerorate.wav", riff(fmt_chunk(1, 1, 0, 16) + chunk("data", "ab")), ErrorCode::kMalformed,
       "sample rate of 0"},
      {"mp3.wav", riff(fmt_chunk(85, 1, 22050, 16) + chunk("data", "ab")), ErrorCode::kMalformed,
       "format tag 85"},
      // Declares 1,000 data bytes, holds 10.
      {"cut.wav", riff(good_fmt) + "data" + le32(1000) + std::string(10, '\0'),
       ErrorCode::kTruncated, "declares 1000 bytes"},
      {"halfheader.wav", riff(good_fmt) + "dat", ErrorCode::kTruncated, "inside a chunk header"},
  };
  for (const Case& c : cases) {
    write_all(path(c.name), c.bytes);
    Result<WavInfo> info = read_wav_info(path(c.name));
    ASSERT_FALSE(info.ok()) << c.name;
    EXPECT_EQ(info.error().code, c.code) << c.name << ": " << info.error().to_string();
    EXPECT_NE(info.error().message.find(path(c.name)), std::string::npos)
        << info.error().message;
    EXPECT_NE(info.error().message.find(c.says), std::string::npos) << info.error().message;
  }
  Result<WavInfo> missing = read_wav_info(path("missing.wav"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_NE(missing.error().message.find(path("missing.wav")), std::string::npos);
}

// ---- Real speech ---------------------------------------------------------------------------

TEST_F(DevicesTest, EspeakWritesAWavWhoseDurationFollowsTheText) {
  EspeakSpeechOutput speech(path("speech"));
  const std::int64_t t0 = 5 * kSecond;
  Result<Utterance> a = speech.say("Hello, how are you today?", t0);
  ASSERT_TRUE(a.ok()) << a.error().to_string();
  EXPECT_EQ(a->wav_path, path("speech") + "/utt_0001.wav");
  EXPECT_TRUE(fs::is_regular_file(a->wav_path));
  EXPECT_EQ(a->start_ns, t0);
  EXPECT_GT(a->duration_ns, kSecond * 3 / 10);
  EXPECT_LT(a->duration_ns, 10 * kSecond);
  Result<WavInfo> info = read_wav_info(a->wav_path);
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->duration_ns, a->duration_ns);
  EXPECT_GT(info->data_bytes, 0u);
  ASSERT_TRUE(speech.current().has_value());
  EXPECT_EQ(*speech.current(), *a);

  // The clock decides what plays.
  EXPECT_FALSE(speech.playing(t0 - 1));
  EXPECT_TRUE(speech.playing(t0));
  EXPECT_TRUE(speech.playing(t0 + a->duration_ns - 1));
  EXPECT_FALSE(speech.playing(t0 + a->duration_ns));

  // A longer text lasts longer; it starts a new file and replaces the first utterance.
  const std::int64_t t1 = t0 + kSecond / 2;
  Result<Utterance> b = speech.say(
      "Can you get out of bed into a chair and back again by yourself, or do you need someone "
      "to help you with it?",
      t1);
  ASSERT_TRUE(b.ok()) << b.error().to_string();
  EXPECT_EQ(b->wav_path, path("speech") + "/utt_0002.wav");
  EXPECT_GT(b->duration_ns, a->duration_ns + kSecond);
  EXPECT_LT(b->duration_ns, 20 * kSecond);
  EXPECT_TRUE(speech.playing(t0 + a->duration_ns + 1));  // the second one plays on

  // Stopping reports how long it played, and only once.
  EXPECT_EQ(speech.stop(t1 + kSecond), kSecond);
  EXPECT_FALSE(speech.playing(t1 + kSecond));
  EXPECT_FALSE(speech.playing(t1 + kSecond / 2));
  EXPECT_EQ(speech.stop(t1 + 2 * kSecond), 0);
  ASSERT_TRUE(speech.current().has_value());
  EXPECT_EQ(speech.current()->text, b->text);

  // Text that looks like an option is still spoken (the "--" before it).
  Result<Utterance> dash = speech.say("-w is not an option here", t1 + 3 * kSecond);
  ASSERT_TRUE(dash.ok()) << dash.error().to_string();
  EXPECT_EQ(dash->wav_path, path("speech") + "/utt_0003.wav");
  EXPECT_FALSE(fs::exists(path("is")));
}

TEST_F(DevicesTest, EspeakFailuresAreValuesNamingTheCommand) {
  EspeakSpeechOutput speech(path("speech"));
  ASSERT_TRUE(speech.say("one", 0).ok());
  const Utterance before = *speech.current();

  // A voice espeak-ng does not have: it exits with status 1.
  EspeakSpeechOutput bad_voice(path("speech2"), "nosuchvoice");
  Result<Utterance> r = bad_voice.say("hello", 0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kIo);
  EXPECT_NE(r.error().message.find("EspeakSpeechOutput::say()"), std::string::npos);
  EXPECT_NE(r.error().message.find("espeak-ng -v nosuchvoice -s 160 -w"), std::string::npos)
      << r.error().message;
  EXPECT_NE(r.error().message.find("exited with status"), std::string::npos) << r.error().message;
  EXPECT_FALSE(bad_voice.current().has_value());

  // A program that is not there.
  EspeakSpeechOutput missing(path("speech3"), "en", 160, path("no/espeak-ng"));
  r = missing.say("hello", 0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kNotFound);
  EXPECT_NE(r.error().message.find(path("no/espeak-ng")), std::string::npos) << r.error().message;

  // A program that exits 0 without writing the WAV: the missing file is named.
  EspeakSpeechOutput silent(path("speech4"), "en", 160, "true");
  r = silent.say("hello", 0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kNotFound);
  EXPECT_NE(r.error().message.find(path("speech4") + "/utt_0001.wav"), std::string::npos)
      << r.error().message;

  // Text checks come first; the current utterance is unchanged by every failure.
  r = speech.say(" \n\t ", 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  r = speech.say(std::string_view("a\0b", 3), 1);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("NUL byte at offset 1"), std::string::npos);
  r = speech.say(std::string(kMaxUtteranceBytes + 1, 'a'), 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kTooLarge);
  EXPECT_EQ(*speech.current(), before);
}

// ---- Simulated speech ----------------------------------------------------------------------

TEST_F(DevicesTest, SimulatedSpeechIsDeterministic) {
  SimulatedSpeechOutput speech(100, 1000);
  EXPECT_FALSE(speech.playing(0));
  EXPECT_EQ(speech.stop(0), 0);
  EXPECT_FALSE(speech.current().has_value());

  Result<Utterance> u = speech.say("  can you   climb\tstairs? ", 50);
  ASSERT_TRUE(u.ok());
  EXPECT_EQ(u->duration_ns, 1000 + 4 * 100);
  EXPECT_EQ(u->start_ns, 50);
  EXPECT_TRUE(u->wav_path.empty());
  EXPECT_TRUE(speech.playing(50 + 1399));
  EXPECT_FALSE(speech.playing(50 + 1400));

  // A new utterance stops the old; stop() after the end reports the whole duration.
  ASSERT_TRUE(speech.say("yes", 2000).ok());
  EXPECT_EQ(speech.current()->text, "yes");
  EXPECT_EQ(speech.stop(5000), 1100);
  ASSERT_TRUE(speech.say("no", 6000).ok());
  EXPECT_EQ(speech.stop(6000 + 300), 300);
  EXPECT_FALSE(speech.playing(6000 + 301));
  ASSERT_EQ(speech.said().size(), 3u);
  EXPECT_EQ(speech.said()[1].text, "yes");

  // The checks of the real device.
  EXPECT_EQ(speech.say("", 0).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(speech.said().size(), 3u);
}

// ---- Screens -------------------------------------------------------------------------------

// The lowest row holding a pixel other than the top-left (background) one, or -1.
int lowest_ink_row(const cv::Mat& img) {
  const cv::Vec3b bg = img.at<cv::Vec3b>(0, 0);
  for (int y = img.rows - 1; y >= 0; --y) {
    for (int x = 0; x < img.cols; ++x) {
      if (img.at<cv::Vec3b>(y, x) != bg) return y;
    }
  }
  return -1;
}

bool uniform(const cv::Mat& img) {
  const cv::Vec3b first = img.at<cv::Vec3b>(0, 0);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      if (img.at<cv::Vec3b>(y, x) != first) return false;
    }
  }
  return true;
}

// The screen's picture as text, to compare with a file's bytes.
std::string image_text(const Screen& screen) {
  return {reinterpret_cast<const char*>(screen.image().data()), screen.image().size()};
}

TEST_F(DevicesTest, OpenCvScreenWritesPngs) {
  OpenCvScreen screen(path("screen"));
  EXPECT_TRUE(screen.image().empty()) << "nothing rendered yet";
  ScreenContent c;
  c.title = "Stairs";
  c.text = "Can you go up and down stairs? Touch an answer or say it.";
  c.options = {"unable", "needs help, verbal, physical, carrying aid", "independent"};
  c.highlighted = 1;
  ASSERT_TRUE(screen.show(c, 0).ok());
  EXPECT_EQ(screen.last_png(), path("screen") + "/screen_0001.png");
  ASSERT_TRUE(screen.current().has_value());
  EXPECT_EQ(*screen.current(), c);
  cv::Mat shown = cv::imread(screen.last_png(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shown.empty());
  EXPECT_EQ(shown.cols, 800);
  EXPECT_EQ(shown.rows, 480);
  EXPECT_FALSE(uniform(shown));
  // image() is the PNG just written, byte for byte.
  EXPECT_EQ(image_text(screen), read_all(screen.last_png()));

  // The highlight changes the picture.
  c.highlighted = -1;
  ASSERT_TRUE(screen.show(c, 1).ok());
  EXPECT_EQ(screen.last_png(), path("screen") + "/screen_0002.png");
  cv::Mat plain = cv::imread(screen.last_png(), cv::IMREAD_COLOR);
  ASSERT_FALSE(plain.empty());
  EXPECT_GT(cv::norm(shown, plain, cv::NORM_L1), 0.0);

  // clear() writes one colour and empties current().
  ASSERT_TRUE(screen.clear(2).ok());
  EXPECT_EQ(screen.last_png(), path("screen") + "/screen_0003.png");
  EXPECT_FALSE(screen.current().has_value());
  cv::Mat blank = cv::imread(screen.last_png(), cv::IMREAD_COLOR);
  ASSERT_FALSE(blank.empty());
  EXPECT_EQ(blank.size(), cv::Size(800, 480));
  EXPECT_TRUE(uniform(blank));
  EXPECT_EQ(image_text(screen), read_all(screen.last_png())) << "the blank picture";
  const std::string blank_png = image_text(screen);

  // Bad content is refused before anything is written.
  c.highlighted = 3;
  Status bad = screen.show(c, 3);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(bad.error().message.find("OpenCvScreen::show(): highlighted 3"), std::string::npos)
      << bad.error().message;
  EXPECT_FALSE(fs::exists(path("screen") + "/screen_0004.png"));
  EXPECT_FALSE(screen.current().has_value());
  EXPECT_EQ(image_text(screen), blank_png) << "a refused show() keeps the picture";
}

TEST_F(DevicesTest, OpenCvScreenWrapsLongTextInsideTheScreen) {
  OpenCvScreen screen(path("screen"), 640, 400);
  ScreenContent shorter{"Feeding", "Can you eat on your own?", {}, -1};
  ASSERT_TRUE(screen.show(shorter, 0).ok());
  cv::Mat a = cv::imread(screen.last_png(), cv::IMREAD_COLOR);
  ScreenContent longer = shorter;
  longer.text =
      "Let's talk about meals. Can you eat on your own, or do you need some help, for example to "
      "cut your food, spread butter or open a carton? Some people need a modified diet, and "
      "that is fine too: just tell me what it is like for you on a normal day. Señora, ¿qué tal?";
  ASSERT_TRUE(screen.show(longer, 1).ok());
  cv::Mat b = cv::imread(screen.last_png(), cv::IMREAD_COLOR);
  ASSERT_EQ(b.size(), cv::Size(640, 400));
  // Several lines: the ink reaches much lower than with one line...
  EXPECT_GT(lowest_ink_row(b), lowest_ink_row(a) + 60);
  // ...and stays off the right margin (no line runs past the width).
  const cv::Vec3b bg = b.at<cv::Vec3b>(0, 0);
  for (int y = 0; y < b.rows; ++y) {
    for (int x = b.cols - 6; x < b.cols; ++x) {
      ASSERT_EQ(b.at<cv::Vec3b>(y, x), bg) << "ink at " << x << "," << y;
    }
  }
}

TEST(HersheyTextTest, AsciiForTheScreenFont) {
  EXPECT_EQ(to_hershey_text("Plain ASCII: 50 yards!"), "Plain ASCII: 50 yards!");
  EXPECT_EQ(to_hershey_text("\u00BFSe\u00F1ora N\u00FA\u00F1ez? \u00A1S\u00ED!"),
            "Senora Nunez? Si!");
  EXPECT_EQ(to_hershey_text("Stra\u00DFe \u00C6 2\u00D73"), "Strasse AE 2x3");
  // One '?' per other character, whatever its length; control characters are spaces.
  EXPECT_EQ(to_hershey_text("\u20AC5 \u4F60\u597D \U0001F600"), "?5 ?? ?");
  EXPECT_EQ(to_hershey_text("a\tb\nc\x7f"), "a b c ");
  EXPECT_EQ(to_hershey_text("bad \xFF\x80 bytes"), "bad ?? bytes");
}

TEST_F(DevicesTest, SimulatedScreenRecordsAndChecks) {
  SimulatedScreen screen;
  ScreenContent c{"Bathing", "Can you bathe by yourself?", {"dependent", "independent"}, 0};
  ASSERT_TRUE(screen.show(c, 10).ok());
  EXPECT_TRUE(screen.image().empty()) << "the simulated screen renders no pictures";
  ASSERT_TRUE(screen.clear(20).ok());
  EXPECT_FALSE(screen.current().has_value());
  c.options.push_back("");
  Status s = screen.show(c, 30);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("SimulatedScreen::show(): option 2 has no label"),
            std::string::npos);
  c.options.assign(kMaxScreenOptions + 1, "x");
  EXPECT_EQ(screen.show(c, 30).error().code, ErrorCode::kTooLarge);
  ASSERT_EQ(screen.history().size(), 2u);
  EXPECT_EQ(screen.history()[0].t_ns, 10);
  EXPECT_EQ(screen.history()[0].content->title, "Bathing");
  EXPECT_EQ(screen.history()[1], (ScreenChange{20, std::nullopt}));
}

// ---- Results -------------------------------------------------------------------------------

TestResult sample_result(int variant = 0) {
  TestResult r;
  r.patient = "María José Núñez";
  r.status = "completed";
  r.items = {{"feeding", 10, "I eat on my own, \"no problem\"", "voice"},
             {"bathing", std::nullopt, "", ""},
             {"stairs", 5 + variant % 2 * 5, "con ayuda\n(with help)", "touch"}};
  r.total = 15 + variant;
  r.finished_ns = 1'234'567'890'123 + variant;
  return r;
}

TEST_F(DevicesTest, JsonResultStoreRoundTrips) {
  JsonResultStore store(path("result.json"));
  EXPECT_FALSE(store.last().has_value());
  const TestResult r = sample_result();
  ASSERT_TRUE(store.store(r).ok());
  ASSERT_TRUE(store.last().has_value());
  EXPECT_EQ(*store.last(), r);
  EXPECT_FALSE(fs::exists(path("result.json.tmp")));

  Result<TestResult> back = load_test_result(path("result.json"));
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(*back, r);

  const std::string text = read_all(path("result.json"));
  nlohmann::json doc = nlohmann::json::parse(text);
  EXPECT_EQ(doc.at("validated_by_clinician"), false);
  EXPECT_TRUE(doc.at("items").at(1).at("score").is_null());
  EXPECT_NE(text.find("\n  \"patient\": "), std::string::npos) << "not pretty: " << text;

  // The memory store encodes the same bytes and gives back the same result.
  MemoryResultStore memory;
  ASSERT_TRUE(memory.store(r).ok());
  EXPECT_EQ(memory.last_json(), text);
  EXPECT_EQ(*memory.last(), r);

  // Invalid UTF-8 is refused by both, naming the field.
  TestResult bad = r;
  bad.items[2].answer = "caf\xC3";
  Status s = store.store(bad);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(s.error().message.find("/items/2/answer"), std::string::npos) << s.error().message;
  EXPECT_EQ(memory.store(bad).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(*store.last(), r);
  EXPECT_EQ(memory.stored_count(), 1);
}

TEST_F(DevicesTest, JsonResultStoreWritesAtomically) {
  const std::string file = path("result.json");
  JsonResultStore store(file);
  ASSERT_TRUE(store.store(sample_result(0)).ok());

  // A reader polling the file while results are rewritten always finds a whole one.
  std::atomic<bool> done{false};
  std::atomic<int> loads{0};
  std::atomic<int> failures{0};
  std::string first_failure;
  std::thread reader([&] {
    while (!done.load()) {
      Result<TestResult> r = load_test_result(file);
      if (!r.ok() || r->patient != "María José Núñez") {
        if (failures.fetch_add(1) == 0) first_failure = r.ok() ? "patient" : r.error().message;
      }
      loads.fetch_add(1);
    }
  });
  for (int i = 1; i <= 150; ++i) ASSERT_TRUE(store.store(sample_result(i)).ok());
  done.store(true);
  reader.join();
  EXPECT_EQ(failures.load(), 0) << first_failure;
  EXPECT_GT(loads.load(), 0);
  EXPECT_EQ(load_test_result(file)->total, 15 + 150);

  // A failed write leaves the previous file whole.
  fs::create_directory(file + ".tmp");
  Status s = store.store(sample_result(7));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find(file + ".tmp"), std::string::npos) << s.error().message;
  EXPECT_EQ(load_test_result(file)->total, 15 + 150);
  EXPECT_EQ(store.last()->total, 15 + 150);
}

TEST_F(DevicesTest, LoadErrorsNameTheFileAndThePointer) {
  const std::string file = path("r.json");
  auto load_error = [&](const std::string& text) {
    write_all(file, text);
    Result<TestResult> r = load_test_result(file);
    EXPECT_FALSE(r.ok()) << text;
    return r.ok() ? Error{} : r.error();
  };
  nlohmann::json good = nlohmann::json::parse(*encode_test_result(sample_result(), "test"));

  Error e = load_error("{\"patient\": ");
  EXPECT_EQ(e.code, ErrorCode::kMalformed);
  EXPECT_NE(e.message.find("load_test_result(): '" + file + "' is not JSON"), std::string::npos)
      << e.message;

  nlohmann::json j = good;
  j["items"][1]["score"] = "five";
  e = load_error(j.dump());
  EXPECT_NE(e.message.find("'" + file + "' at /items/1/score: expected an integer or null, got "
                           "string"),
            std::string::npos)
      << e.message;

  j = good;
  j.erase("status");
  e = load_error(j.dump());
  EXPECT_NE(e.message.find("at /status: missing"), std::string::npos) << e.message;

  j = good;
  j["items"][0]["score"] = 2.5;
  e = load_error(j.dump());
  EXPECT_NE(e.message.find("at /items/0/score"), std::string::npos) << e.message;

  j = good;
  j["total"] = 1LL << 40;
  e = load_error(j.dump());
  EXPECT_NE(e.message.find("at /total: 1099511627776 is out of range"), std::string::npos)
      << e.message;

  j = good;
  j["validated_by_clinician"] = "yes";
  e = load_error(j.dump());
  EXPECT_NE(e.message.find("at /validated_by_clinician"), std::string::npos) << e.message;

  e = load_error("[1, 2]");
  EXPECT_NE(e.message.find("at the root: expected an object, got array"), std::string::npos)
      << e.message;

  // Unknown fields are ignored; a clinician's validation is readable.
  j = good;
  j["validated_by_clinician"] = true;
  j["clinician"] = "Dr. Ruiz";
  write_all(file, j.dump());
  Result<TestResult> ok = load_test_result(file);
  ASSERT_TRUE(ok.ok()) << ok.error().to_string();
  EXPECT_EQ(*ok, sample_result());

  Result<TestResult> missing = load_test_result(path("nope.json"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_NE(missing.error().message.find(path("nope.json")), std::string::npos);
}

// ---- Pagers --------------------------------------------------------------------------------

TEST_F(DevicesTest, FilePagerAppendsJsonLines) {
  const std::string file = path("pager.jsonl");
  write_all(file, "{\"t_ns\":1,\"message\":\"earlier\"}\n");
  FilePager pager(file);
  ASSERT_TRUE(pager.page("Patient asks for help in room 12", 1'000).ok());
  ASSERT_TRUE(pager.page("Two lines:\n\"quoted\" and ünïcode", 2'000).ok());
  EXPECT_EQ(pager.sent(),
            (std::vector<std::string>{"Patient asks for help in room 12",
                                      "Two lines:\n\"quoted\" and ünïcode"}));

  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "{\"t_ns\":1,\"message\":\"earlier\"}");
  nlohmann::json second = nlohmann::json::parse(lines[1]);
  EXPECT_EQ(second.at("t_ns"), 1'000);
  EXPECT_EQ(second.at("message"), "Patient asks for help in room 12");
  nlohmann::json third = nlohmann::json::parse(lines[2]);
  EXPECT_EQ(third.at("t_ns"), 2'000);
  EXPECT_EQ(third.at("message"), "Two lines:\n\"quoted\" and ünïcode");

  // Refused pages leave the file alone; the memory pager refuses the same and writes the same.
  EXPECT_EQ(pager.page("", 3'000).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(pager.page("\xFF", 3'000).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(pager.page(std::string(kMaxPageBytes + 1, 'x'), 3'000).error().code,
            ErrorCode::kTooLarge);
  EXPECT_EQ(pager.sent().size(), 2u);
  MemoryPager memory;
  ASSERT_TRUE(memory.page("Patient asks for help in room 12", 1'000).ok());
  ASSERT_TRUE(memory.page("Two lines:\n\"quoted\" and ünïcode", 2'000).ok());
  EXPECT_EQ(memory.page("", 3'000).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(memory.sent(), pager.sent());
  ASSERT_EQ(memory.lines().size(), 2u);
  EXPECT_EQ(memory.lines()[0] + memory.lines()[1],
            read_all(file).substr(lines[0].size() + 1));

  // A pager whose file cannot be opened says which.
  FilePager nowhere(path("no/such/dir/pager.jsonl"));
  Status s = nowhere.page("hello", 0);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find(path("no/such/dir/pager.jsonl")), std::string::npos);
  EXPECT_TRUE(nowhere.sent().empty());
}

}  // namespace
}  // namespace quiver::agents::devices
