-- tb_drum_diameter: the drum-diameter study of thesis 5.3.3 (Table 5.1): the open-loop stroke of tb_stroke
-- (13 V, from fully open into the top frame) with the cable drum diameter as the varied design parameter.
-- bench: drum-diameter-sweep; parameter set: params/rail_wr_8p5nm.txt
-- measurement: params/measurements/table5_1_drum_diameter.csv
--
-- Circuit: study (tb_stroke with drum_diameter mapped); the observables are those of tb_stroke below
-- "study.", e.g. study.mechanism.drum.angle [rad] (drum revolutions) and study.door.pane.pos [m].
-- Generics: drum_diameter, u_supply.
entity tb_drum_diameter is
  generic (
    u_supply      : real := 13.0;    -- [V] battery voltage
    drum_diameter : real := 0.044);  -- [m] cable drum diameter (Table 5.1: 40, 42, 44, 46, 48 mm)
end entity tb_drum_diameter;

architecture structural of tb_drum_diameter is
begin
  study: entity work.tb_stroke(structural)
    generic map (u_supply => u_supply, drum_diameter => drum_diameter);
end architecture structural;
