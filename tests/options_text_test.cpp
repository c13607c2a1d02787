// pnf::parse_units and pnf::parse_backend_and_device: the one reading of --units, --backend and
// --device (CLI) and units=, backend=, device= (Python).
#include "pnf/options_text.hpp"

#include <gtest/gtest.h>

#include <string>

#include "pnf/error.hpp"

namespace pnf {
namespace {

// The message of the pnf::Error(invalid_argument) that `call` throws, or a failure.
template <typename Call>
std::string refusal(Call&& call) {
  try {
    call();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "nothing was refused";
  return "";
}

TEST(ParseUnits, ReadsWhatToStringWrites) {
  for (const Units units : {Units::radius, Units::absolute}) EXPECT_EQ(parse_units(to_string(units)), units);
  EXPECT_EQ(parse_units(to_string(FilterParams{}.units)), FilterParams{}.units);
  const std::string message = refusal([] { (void)parse_units("metres"); });
  EXPECT_NE(message.find("'metres'"), std::string::npos) << message;
  EXPECT_NE(message.find("'radius' or 'absolute'"), std::string::npos) << message;
  (void)refusal([] { (void)parse_units(""); });
}

TEST(ParseBackendAndDevice, OpenClTakesEveryDeviceForm) {
  EXPECT_EQ(parse_backend_and_device("opencl", ""), Device::opencl());
  EXPECT_EQ(parse_backend_and_device("opencl", "gpu"), Device::opencl("gpu"));
  EXPECT_EQ(parse_backend_and_device("opencl", "opencl:1:0"), Device::opencl("1:0"));
  EXPECT_EQ(parse_backend_and_device("opencl", "reference"), Device::reference());
}

TEST(ParseBackendAndDevice, ReferenceTakesNoOpenClDevice) {
  EXPECT_EQ(parse_backend_and_device("reference", ""), Device::reference());
  EXPECT_EQ(parse_backend_and_device("reference", "Reference"), Device::reference());
  for (const std::string device : {"gpu", "opencl", "opencl:cpu", "0:0", "pocl"}) {
    const std::string message = refusal([&] { (void)parse_backend_and_device("reference", device); });
    EXPECT_NE(message.find("backend 'reference'"), std::string::npos) << message;
    EXPECT_NE(message.find("device '" + device + "'"), std::string::npos) << message;
  }
}

TEST(ParseBackendAndDevice, UnknownBackendAndEmptySelectorAreRefused) {
  const std::string message = refusal([] { (void)parse_backend_and_device("cuda", ""); });
  EXPECT_NE(message.find("backend 'cuda'"), std::string::npos) << message;
  (void)refusal([] { (void)parse_backend_and_device("opencl", "opencl:"); });
}

}  // namespace
}  // namespace pnf
