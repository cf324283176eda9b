// tests/models/urdf_helpers.hpp: what the URDF tests share: the data files' paths, the message
// of a refused URDF text, and a one-joint robot with extra elements.
#pragma once

#include <string>

#include "varsym/models/robot.hpp"

namespace urdf_test {

using namespace varsym;

inline std::string data(const std::string& file) {
    return VARSYM_TEST_DATA "/urdf/" + file;
}

/// The message of the urdf_error that parsing `xml` throws ("" if none).
inline std::string refusal(const std::string& xml) {
    try {
        (void)models::parse_urdf(xml, "test.urdf");
    } catch (const models::urdf_error& e) {
        return e.what();
    }
    return "";
}

inline std::string robot(const std::string& extra, const std::string& joint_type = "revolute",
                         const std::string& inertia = "ixx=\"1\" iyy=\"1\" izz=\"1\"") {
    return "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"><inertial><mass value=\"1\"/>"
           "<inertia " +
           inertia + "/></inertial></link><joint name=\"j\" type=\"" + joint_type +
           "\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/></joint>" + extra +
           "</robot>";
}

} // namespace urdf_test
