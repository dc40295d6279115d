// The importer: a user's table and its mapping (import_mapping.h) in, a cellmetry recording
// (recording.h, mm and rad) out — what `cellmetry import MAPPING.yaml -o FOLDER` writes.
//
// Contract:
//  - The tables' rows are joined into one row each (table_join.h), the importer's rows.
//  - Every column the mapping names must be in a table; one that is not is an InputError at
//    the mapping's line and column, with the nearest column name (or the header).
//  - Rows become samples: each row is one sample, or (samples: {column}) the rows sharing a value
//    are one, and must then agree on the joints and facts. Samples are numbered 0, 1, ... in
//    order of first appearance; so are poses (poses: {column}, or consecutive samples whose
//    joints agree within a tolerance; otherwise each sample is its own pose).
//  - Every observation entry reads one target pose per row, converted to mm and rad, turned into
//    the target's pose in the camera (T_camera_target) when the table holds the camera's pose
//    in the target. A row that leaves all of an entry's cells empty did not see that target;
//    one that fills some of them is an error.
//  - An entry's position uncertainty columns give the observation's covariance: diagonal, each
//    (U / k)^2 in mm^2 (U the cell, k the entry's coverage factor); its rotation sigma the
//    rotation's, diagonal, sigma^2 in rad^2.
//  - Every cell is checked where it is (file:line:column, with its data row): not a number,
//    not finite, beyond any measurement (a position beyond 100 m, a joint beyond 100 rad, an
//    Euler, roll-pitch-yaw or rotation-vector angle beyond a full turn), a
//    rotation matrix not orthonormal, a quaternion not unit within its tolerance, a name with a
//    comma, a target not under `targets:`, rows of one sample that disagree, an uncertainty
//    that is not positive.
#pragma once

#include <string>

#include "cellmetry/formats/recording.h"
#include "cellmetry/import/data_table.h"
#include "cellmetry/import/import_mapping.h"
#include "cellmetry/import/table_join.h"

namespace cellmetry {

// The mapping's tables, each read as CSV or JSON lines as the mapping says, their rows joined
// as it says (table_join.h).
JoinedTable ReadMappedTables(const ImportMapping& mapping);

// The recording the joined rows hold under the mapping.
Recording ImportTable(const ImportMapping& mapping, const JoinedTable& table);

// ReadImportMapping, ReadMappedTables, ImportTable.
Recording ImportRecording(const std::string& mapping_path);

}  // namespace cellmetry
