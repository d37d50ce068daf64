#pragma once
/// The numbers of a URDF file, checked before urdfdom reads it. urdfdom drops a <collision> or
/// <visual> whose shape it cannot read (logging, not failing), and reads "nan", "inf" and 1e999 as
/// numbers: a robot would lose a link's solid, or carry a non-finite size, without a word.
#include <cstdint>

#include <string>

#include "core/diagnostics.h"
#include "core/source.h"
#include "load/spec.h"

class TiXmlBase;
class TiXmlDocument;
class TiXmlElement;

namespace sscs {

/// Where an XML element or attribute of `file` is.
SourceMark xml_mark(uint32_t file, const TiXmlBase& at);

/// Reads the robot file (`what`: "URDF file" or "SRDF file") that type file `type_file` names at
/// `at`, like every input file (project root, size limit, not a FIFO), into `sources` as `file`
/// and parses it into `doc`: its top <robot> element, or null after reporting why not (missing,
/// unreadable, malformed XML at its line and column, no <robot> at the top).
const TiXmlElement* read_robot_xml(const char* what, const std::string& type_file, const Scalar& at, Sources& sources,
                                   Diagnostics& diag, TiXmlDocument& doc, uint32_t& file);

/// Reports to `diag`, at the attribute or element in `file` (the URDF's source), every number of
/// `robot` (the URDF's <robot> element) that is not finite or not there: origins, axes, shapes,
/// inertials, limits, safety controllers, dynamics, mimics and colours. Also a shape element that
/// is missing or unknown in a <geometry>, a mesh without a filename, a negative mass and a colour
/// channel outside 0..1.
void check_urdf_numbers(const TiXmlElement& robot, uint32_t file, Diagnostics& diag);

/// Reports, at its element in `file`, what makes the links no tree or the file one urdfdom
/// refuses without a place: a link that is the child of two joints, joints that close a loop
/// of links (urdfdom's messages do not name the loop), link or joint names given twice, a
/// joint's missing or unknown parent or child link, a revolute or prismatic joint without
/// <limit>, a <mimic> without joint=, and a second root link.
void check_urdf_tree(const TiXmlElement& robot, uint32_t file, Diagnostics& diag);

}  // namespace sscs
