N000 L3 ; decode the position into @0
N001 G01 X@0 FX0
N002 M30
