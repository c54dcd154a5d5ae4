"""Writes shapefile zips with pyshp for coverplan's import tests, and the positions they hold.

usage: make_shapefiles.py OUT_DIR

A field near Zurich with a hole, and a no-fly zone marked by its `kind` attribute, written as:
  field-wgs84.zip   longitude/latitude, WGS84 .prj
  field-utm.zip     UTM zone 32N metres (converted with the `utm` package), its .prj
  no-prj.zip        without the .prj
  wrong-winding.zip the field's outer ring wound counter-clockwise (as a hole)
  other-crs.zip     a .prj of another reference system (ETRS89 / LAEA Europe)
expected.json holds the field, hole and zone as [lon, lat] rings.
"""

import io
import json
import sys
import zipfile
from pathlib import Path

import shapefile
import utm

FIELD = [(8.540, 47.370), (8.556, 47.370), (8.556, 47.382), (8.540, 47.382)]
HOLE = [(8.546, 47.374), (8.548, 47.374), (8.548, 47.376), (8.546, 47.376)]
ZONE = [(8.550, 47.378), (8.552, 47.378), (8.552, 47.380), (8.550, 47.380)]

WGS84_PRJ = ('GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,298.257223563]],'
             'PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]]')
UTM32N_PRJ = ('PROJCS["WGS_1984_UTM_Zone_32N",GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",'
              'SPHEROID["WGS_1984",6378137.0,298.257223563]],PRIMEM["Greenwich",0.0],'
              'UNIT["Degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],'
              'PARAMETER["False_Easting",500000.0],PARAMETER["False_Northing",0.0],'
              'PARAMETER["Central_Meridian",9.0],PARAMETER["Scale_Factor",0.9996],'
              'PARAMETER["Latitude_Of_Origin",0.0],UNIT["Meter",1.0]]')
LAEA_PRJ = ('PROJCS["ETRS89_LAEA_Europe",GEOGCS["GCS_ETRS_1989",DATUM["D_ETRS_1989",'
            'SPHEROID["GRS_1980",6378137.0,298.257222101]],PRIMEM["Greenwich",0.0],'
            'UNIT["Degree",0.0174532925199433]],PROJECTION["Lambert_Azimuthal_Equal_Area"],'
            'PARAMETER["False_Easting",4321000.0],PARAMETER["False_Northing",3210000.0],'
            'PARAMETER["Central_Meridian",10.0],PARAMETER["Latitude_Of_Origin",52.0],UNIT["Meter",1.0]]')


def signed_area(ring):
    return sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(ring, ring[1:] + ring[:1])) / 2


def wound(ring, clockwise):
    """The ring closed and wound as asked (shapefiles: outer rings clockwise, holes counter-clockwise)."""
    ring = list(ring)
    if (signed_area(ring) < 0) != clockwise:
        ring.reverse()
    return ring + ring[:1]


def to_utm(point):
    easting, northing, _, _ = utm.from_latlon(point[1], point[0], force_zone_number=32)
    return (float(easting), float(northing))


def write(path, records, prj, project=lambda p: p):
    shp, shx, dbf = io.BytesIO(), io.BytesIO(), io.BytesIO()
    w = shapefile.Writer(shp=shp, shx=shx, dbf=dbf, shapeType=shapefile.POLYGON)
    w.field("name", "C", size=40)
    w.field("kind", "C", size=20)
    for rings, name, kind in records:
        w.poly([[project(p) for p in ring] for ring in rings])
        w.record(name, kind)
    w.close()
    stem = Path(path).stem
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr(f"{stem}.shp", shp.getvalue())
        z.writestr(f"{stem}.shx", shx.getvalue())
        z.writestr(f"{stem}.dbf", dbf.getvalue())
        if prj is not None:
            z.writestr(f"{stem}.prj", prj)


def main(out):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    good = [([wound(FIELD, True), wound(HOLE, False)], "North field", "field"), ([wound(ZONE, True)], "Mast", "nfz")]
    write(out / "field-wgs84.zip", good, WGS84_PRJ)
    write(out / "field-utm.zip", good, UTM32N_PRJ, to_utm)
    write(out / "no-prj.zip", good, None)
    write(out / "wrong-winding.zip", [([wound(FIELD, False)], "North field", "field")], WGS84_PRJ)
    write(out / "other-crs.zip", good, LAEA_PRJ)
    (out / "expected.json").write_text(json.dumps({"field": FIELD, "hole": HOLE, "zone": ZONE}))


if __name__ == "__main__":
    main(sys.argv[1])
