// Tests shared/articula/status.h: every code has a distinct name and text, unknown codes are
// labelled as such, and docs/protocol.md's error-code table matches the header exactly.
#include <articula/status.h>
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace articula;

namespace {

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

// Cells of a Markdown table row "| a | b | c |" (empty when the line is not one).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  const std::string t = trim(line);
  if (t.size() < 2 || t.front() != '|' || t.back() != '|') return out;
  std::string cell;
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i] == '|') {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += t[i];
    }
  }
  return out;
}

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

struct Row {
  std::string name, text;
};

}  // namespace

TEST(Status, NamesAndTextsDistinctAndNonEmpty) {
  ASSERT_GT(kStatusCount, 10);
  std::set<std::string> names, texts;
  for (int code = 0; code < kStatusCount; ++code) {
    const std::string name = status_name(uint8_t(code)), text = status_text(uint8_t(code));
    EXPECT_FALSE(name.empty()) << code;
    EXPECT_FALSE(text.empty()) << code;
    EXPECT_NE(text, "unknown status") << code;
    EXPECT_NE(name, "Unknown") << code;
    EXPECT_NE(name[0], 'k') << code;  // the k prefix is dropped
    for (char c : name) EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(c))) << name;
    names.insert(name);
    texts.insert(text);
  }
  EXPECT_EQ(names.size(), size_t(kStatusCount));
  EXPECT_EQ(texts.size(), size_t(kStatusCount));
}

TEST(Status, UnknownCodes) {
  for (int code = kStatusCount; code < 256; ++code) {
    EXPECT_STREQ(status_text(uint8_t(code)), "unknown status") << code;
    EXPECT_STREQ(status_name(uint8_t(code)), "Unknown") << code;
  }
}

TEST(Status, EnumValuesAreTheCodes) {
  // The codes the protocol promises never to renumber (docs/protocol.md).
  EXPECT_EQ(kOk, 0);
  EXPECT_EQ(kEmptyLine, 1);
  EXPECT_EQ(kUnknownCommand, 2);
  EXPECT_EQ(kBadNumber, 3);
  EXPECT_EQ(kMissingArgument, 4);
  EXPECT_EQ(kExtraArgument, 5);
  EXPECT_EQ(kBadJoint, 6);
  EXPECT_EQ(kLineTooLong, 7);
  EXPECT_EQ(kValueOutOfRange, 8);
  EXPECT_EQ(kJointLimit, 9);
  EXPECT_EQ(kUnreachable, 10);
  EXPECT_EQ(kBadCharacter, 11);
  EXPECT_EQ(kNotHomed, 12);
  EXPECT_EQ(kSettingUnknown, 13);
  EXPECT_EQ(kSettingsReset, 14);
  EXPECT_EQ(kStopped, 15);
  EXPECT_EQ(kNoClosedForm, 16);
  EXPECT_EQ(kConfigChecksum, 17);
  EXPECT_EQ(kConfigInvalid, 18);
  EXPECT_EQ(kLineNotFollowed, 19);
  EXPECT_EQ(kPinUnavailable, 20);
  EXPECT_EQ(kInputTimeout, 21);
  EXPECT_EQ(kStatusCount, 22);
  EXPECT_STREQ(status_name(kLineTooLong), "LineTooLong");
  EXPECT_STREQ(status_text(kOk), "ok");
}

TEST(Status, ProtocolDocTableMatchesHeader) {
  const std::string path = ARTICULA_SOURCE_DIR "/docs/protocol.md";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::map<int, Row> doc;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::vector<std::string> c = cells(line);
    // Rows of the error-code table: three cells, the first a number.
    if (c.size() != 3 || !all_digits(c[0])) continue;
    const int code = std::stoi(c[0]);
    ASSERT_EQ(doc.count(code), 0u) << "code " << code << " listed twice (line " << lineno << ")";
    // Names may be written as code (`Name`) in the doc.
    std::string name = c[1];
    if (name.size() >= 2 && name.front() == '`' && name.back() == '`') name = name.substr(1, name.size() - 2);
    doc[code] = Row{name, c[2]};
  }
  ASSERT_FALSE(doc.empty()) << "no error-code table found in " << path;
  // Every code of the header is in the doc, with its name and text...
  for (int code = 0; code < kStatusCount; ++code) {
    const auto it = doc.find(code);
    if (it == doc.end()) {
      ADD_FAILURE() << "docs/protocol.md lacks code " << code << " (" << status_name(uint8_t(code)) << ")";
      continue;
    }
    EXPECT_EQ(it->second.name, status_name(uint8_t(code))) << "code " << code;
    EXPECT_EQ(it->second.text, status_text(uint8_t(code))) << "code " << code;
  }
  // ...and the doc lists nothing else.
  for (const auto& kv : doc)
    EXPECT_LT(kv.first, int(kStatusCount)) << "docs/protocol.md lists code " << kv.first << " (" << kv.second.name
                                           << "), which status.h does not have";
  EXPECT_EQ(doc.size(), size_t(kStatusCount));
}
