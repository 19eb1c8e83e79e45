// Text clouds: a header row chooses x, y, z by name; decimal commas, thousands separators and
// ';'-separated fields are refused with the line, the column and the text, never guessed.
#include <catch2/catch.hpp>
#include <string>

#include "quirk_files.hpp"

using io_quirks::expect_points;
using io_quirks::expect_refused;

TEST_CASE("CSV header: x, y, z are chosen by name wherever they stand", "[io][xyz][columns]") {
  const std::vector<Eigen::Vector3d> p = {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6)};
  expect_points("normals_first.csv", "nx,ny,nz,x,y,z\n0,0,1,1,2,3\n0,1,0,4,5,6\n", p);
  expect_points("zyx.csv", "z,y,x\n3,2,1\n6,5,4\n", p);
  expect_points("upper.csv", "X,Y,Z,Intensity\n1,2,3,9\n4,5,6,9\n", p);
  expect_points("cloudcompare.txt", "//X,Y,Z,R,G,B\n1,2,3,255,0,0\n4,5,6,0,255,0\n", p);
  expect_points("cloudcompare_blanks.txt", "//X Y Z Nx Ny Nz\n1 2 3 0 0 1\n4 5 6 0 0 1\n", p);
  expect_points("quoted.csv", "\"y\",\"x\",\"z\"\n2,1,3\n5,4,6\n", p);
  expect_points("spaced.csv", "z, x ,  y\n3, 1, 2\n6 ,4 ,5\n", p);
  expect_points("blank_header.xyz", "nx ny nz x y z\n0 0 1 1 2 3\n0 1 0 4 5 6\n", p);
}

TEST_CASE("CSV header without x, y, z names: the first three columns", "[io][xyz][columns]") {
  expect_points("named.csv", "easting,northing,height,i\n1,2,3,7\n", {Eigen::Vector3d(1, 2, 3)});
}

TEST_CASE("CSV header naming only some of x, y, z, or one twice, is refused",
          "[io][xyz][columns]") {
  expect_refused("partial.csv", "x,y,intensity\n1,2,3\n", {"line 1", "no column 'z'"});
  expect_refused("twice.csv", "x,y,z,X\n1,2,3,4\n", {"line 1", "'x' twice", "fields 1 and 4"});
}

TEST_CASE("Data lines must have as many fields as the header names", "[io][xyz][columns]") {
  expect_refused("short.csv", "nx,ny,nz,x,y,z\n0,0,1,1,2\n",
                 {"line 2", "found 5 fields", "header (line 1) names 6"});
}

TEST_CASE("Decimal commas are refused with the line, column and text", "[io][xyz][locale]") {
  expect_refused("comma_decimal.xyz", "1,5 2,0 3,25\n", {"line 1", "column 1", "'1,5'"});
  expect_refused("comma_decimal_tab.txt", "0.5 1 2\n1,5\t2,0\t3,25\n",
                 {"line 2", "column 1", "'1,5'", "decimal comma"});
  expect_refused("comma_decimal_late.xyz", "1.5 2 3\n4 5,5 6\n", {"line 2", "column 3", "'5,5'"});
  expect_refused("header_comma_decimal.xyz", "x y z\n1,5 2,0 3,25\n",
                 {"line 2", "column 1", "'1,5'"});
}

TEST_CASE("Thousands separators are refused with the line, column and text", "[io][xyz][locale]") {
  expect_refused("thousands.xyz", "1.0 2.0 3.0\n5,632.500 1.0 2.0\n",
                 {"line 2", "column 1", "'5,632.500'", "thousands separator"});
  // In a CSV the comma splits the number: the field count no longer matches the header.
  expect_refused("thousands.csv", "x,y,z\n1.5,2,3\n5,632.500,1.0,2.0\n",
                 {"line 3", "found 4 fields", "header (line 1) names 3", "thousands separator",
                  "'5,632.500,1.0,2.0'"});
  // Without a header, against the first data line.
  expect_refused("thousands_noheader.csv", "1.5,2,3\n5,632.500,1.0,2.0\n",
                 {"line 2", "found 4 fields", "line 1 has 3", "'5,632.500,1.0,2.0'"});
}

TEST_CASE("Semicolon-separated fields are refused", "[io][xyz][locale]") {
  expect_refused("excel.csv", "1,5;2,0;3,25\n", {"line 1", "column 4", "';'"});
  expect_refused("excel_header.csv", "x;y;z\n1,5;2;3\n", {"line 1", "column 2"});
}

TEST_CASE("Comma-separated lines with blanks around the commas still read", "[io][xyz][columns]") {
  expect_points("spaces.csv", "1, 2, 3\n4 ,5 ,6\n 7 , 8 , 9 \n",
                {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6), Eigen::Vector3d(7, 8, 9)});
}

TEST_CASE("PTS: a count line, then points, reads as before", "[io][xyz][columns]") {
  expect_points("scan.pts", "2\n1 2 3 100 255 0 0\n4 5 6 100 0 255 0\n",
                {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6)});
  expect_refused("bad_count.pts", "3\n1 2 3\n", {"line 1 announces 3 points", "holds 1"});
}
